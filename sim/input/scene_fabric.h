/* scene_fabric.h — a material's `fabric` in measured units, converted to SI, and the
 * plausibility warnings of a loaded scene (scene_fabric.c; docs/fabrics.md): internal to the
 * scene loader. */
#ifndef SW_SCENE_FABRIC_H
#define SW_SCENE_FABRIC_H

#include "scene_yaml.h"

/* What a fabric set (besides the density, which it always sets). */
enum { SC_FABRIC_BENDING = 1, SC_FABRIC_MEMBRANE = 2, SC_FABRIC_DDE = 4 /* preset or data */ };

/* The ranges outside which a scene's number draws a warning (docs/fabrics.md, "Warnings"). */
#define SC_PLAUSIBLE_SIZE 10.0          /* m: the largest extent of a cloth */
#define SC_PLAUSIBLE_DENSITY_MIN 0.01   /* kg/m^2 (10 g/m^2) */
#define SC_PLAUSIBLE_DENSITY_MAX 2.0    /* kg/m^2 (2000 g/m^2) */
#define SC_PLAUSIBLE_BENDING_MAX 1e-2   /* N m */
#define SC_PLAUSIBLE_TENSILE_MAX 1e6    /* N/m */

/* `fabric: {...}` of the material or panel `what` into mat; *set says what it set. */
int sc_load_fabric(const ctx *c, const ynode *y, const char *what, sw_material *mat, int *set);
/* The bias bending rigidity when a scene gives only warp and weft ones (N m; docs/models.md
 * "Anisotropic bending"). */
double sc_bend_bias_default(double ku, double kv);
/* Warnings (appended to m->warning) for numbers a garment user mistypes: a cloth over 10 m
 * across, a density outside 10 g/m^2 to 2 kg/m^2, a bending stiffness over 1e-2 N m, a
 * tensile stiffness over 1e6 N/m. */
void sc_plausibility(const ctx *c);

/* The measured fabrics shipped in data/fabrics/ (sim/input/fabric_presets.c, written from the
 * files by tools/fabric_presets.py): name, the file's path in the source tree, its text. */
typedef struct sc_fabric_preset {
  const char *name, *file, *json;
} sc_fabric_preset;
extern const sc_fabric_preset sc_fabric_presets[];
extern const int sc_nfabric_presets;
const sc_fabric_preset *sc_fabric_preset_find(const char *name);
/* A fabric in the data set's own format (scene_dde.c): the text buf of len bytes, `name` for
 * messages, into dd; 0, or -1 with err "name:line:column: what was found; expected what". */
int sc_dde_parse(const char *name, const char *buf, size_t len, sw_dde *dd, char *err,
                 size_t errsz);
int sc_dde_read(const char *path, sw_dde *dd, char *err, size_t errsz);
/* The rigidities (N m) of strips cut along warp, along weft and at 45 degrees, bent to small
 * curvature (the data's first column, a quarter of its number: models/dde.c): a strip along
 * warp folds about hinges across it. */
void sc_dde_strips(const sw_dde *dd, double kb[3]);

/* The conversions (SI from each measured unit), for the tests. */
double sc_fabric_kes_b(double gf_cm2_per_cm);   /* N m */
double sc_fabric_kes_g(double gf_per_cm_deg);   /* N/m per rad */
double sc_fabric_e100(double percent);          /* N/m */
double sc_fabric_cantilever(double gsm, double c_cm); /* N m */

#endif
