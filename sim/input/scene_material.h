/* scene_material.h — the material, panel and damping keys of a scene (scene_material.c) and
 * its tendons (scene_tendon.c): internal to the scene loader. */
#ifndef SW_SCENE_MATERIAL_H
#define SW_SCENE_MATERIAL_H

#include "scene_yaml.h"

/* `material` into mat[0]; me and obj (the mesh and its name) for the (u,v) check. */
int sc_load_material(const ctx *c, const ynode *y, const sw_mesh *me, const char *obj);
/* `panels` after the geometry is filled: mat[1..], face_mat, per-panel uv_scale (relative to
 * the mesh's mesh_scale). */
int sc_load_panels(const ctx *c, const ynode *y, const sw_mesh *me, const char *obj,
                   double mesh_scale);
/* `damping: {mass: alpha, stiffness: beta}` (Rayleigh). */
int sc_load_damping(const ctx *c, const ynode *y);
/* `tendons` after the geometry is filled (x0 gives relative rest lengths). */
int sc_load_tendons(const ctx *c, const ynode *y);
/* scene_files.c: read the OBJ file that y names (a path relative to the scene's folder) into
 * mesh (its full path into path, SW_PATHSZ bytes); what names the key in messages ("mesh obj"). */
int sc_read_obj(const ctx *c, const ynode *y, const char *what, sw_mesh *mesh, char *path);
/* scene_files.c: remember a file the scene read (buf NULL: read path again) in m->input, for
 * resumes. */
int sc_note_input(const ctx *c, const ynode *y, const char *path, const char *buf, size_t len);
/* `obstacles` (scene_contact.c). */
int sc_load_obstacles(const ctx *c, const ynode *y);
/* `contact` (y NULL: the defaults), which needs obstacles. */
int sc_load_contact(const ctx *c, const ynode *y, int has_obstacles);
/* `seams`, `sewing` and `fit` (scene_seam.c; each may be NULL): the seams' curves, checked and
 * paired; after the panels and the arrangement. */
int sc_load_seams(const ctx *c, const ynode *seams, const ynode *sewing, const ynode *fit);
/* The OBJ group called name into *g; else -1 with "W SAYS 'name', which is no group of the
 * mesh; expected one of: ..." at `at` (scene_seam.c). */
int sc_find_group(const ctx *c, const ynode *at, const char *w, const char *says,
                  const char *name, int *g);
/* `arrange` (scene_arrange.c): each named piece's x0 from its flat pattern, placed on a
 * cylinder or rigidly, checked against the mesh obstacles and the other pieces. */
int sc_load_arrange(const ctx *c, const ynode *y);
/* Multiply every elastic stiffness of a loaded model (before sw_model_finish) by s > 0 and
 * record s in m->stiffness_scale (sw_scene_overrides in sinew.h says which). */
void sc_scale_stiffness(sw_model *m, double s);
#endif
