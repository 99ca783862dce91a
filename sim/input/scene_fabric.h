/* scene_fabric.h — a material's `fabric` in measured units, converted to SI, and the
 * plausibility warnings of a loaded scene (scene_fabric.c; docs/fabrics.md): internal to the
 * scene loader. */
#ifndef SW_SCENE_FABRIC_H
#define SW_SCENE_FABRIC_H

#include "scene_yaml.h"

/* What a fabric set (besides the density, which it always sets). */
enum { SC_FABRIC_BENDING = 1, SC_FABRIC_MEMBRANE = 2 };

/* The ranges outside which a scene's number draws a warning (docs/fabrics.md, "Warnings"). */
#define SC_PLAUSIBLE_SIZE 10.0          /* m: the largest extent of a cloth */
#define SC_PLAUSIBLE_DENSITY_MIN 0.01   /* kg/m^2 (10 g/m^2) */
#define SC_PLAUSIBLE_DENSITY_MAX 2.0    /* kg/m^2 (2000 g/m^2) */
#define SC_PLAUSIBLE_BENDING_MAX 1e-2   /* N m */
#define SC_PLAUSIBLE_TENSILE_MAX 1e6    /* N/m */

/* `fabric: {...}` of the material or panel `what` into mat; *set says what it set. */
int sc_load_fabric(const ctx *c, const ynode *y, const char *what, sw_material *mat, int *set);
/* Warnings (appended to m->warning) for numbers a garment user mistypes: a cloth over 10 m
 * across, a density outside 10 g/m^2 to 2 kg/m^2, a bending stiffness over 1e-2 N m, a
 * tensile stiffness over 1e6 N/m. */
void sc_plausibility(const ctx *c);

/* The conversions (SI from each measured unit), for the tests. */
double sc_fabric_kes_b(double gf_cm2_per_cm);   /* N m */
double sc_fabric_kes_g(double gf_per_cm_deg);   /* N/m per rad */
double sc_fabric_e100(double percent);          /* N/m */
double sc_fabric_cantilever(double gsm, double c_cm); /* N m */

#endif
