/* Tethers (long-range attachments; Kim, Chentanez & Müller 2012, "Long range attachments"; the
   tether constraints of NvCloth): each free particle of a cloth with `tethers` > 0 may not get
   farther from any of its CVK_TETHER_SLOTS nearest pins than tethers × its rest distance to
   that pin across the cloth. One-sided and per particle, so one pass after each outer
   iteration holds them exactly, whatever the size of the cloth; the local sweeps alone let a
   long hanging cloth stretch in proportion to its length.

   Rest distance: a grid's rest shape is a flat rectangle, convex, so its geodesic distances
   are straight lines: rest_scale × the distance between the two particles' initial positions.
   A mesh cloth's is the shortest path along its springs' rest lengths, which is at least the
   geodesic (a path across triangles is no shorter than the surface's): the tether never pulls
   a particle closer than the true rest distance allows. Nearest pins are nearest along the
   springs, in both cases. */
#ifndef CVK_TETHER_H
#define CVK_TETHER_H

#include "build.h"

#define CVK_TETHER_SLOTS 4u
#define CVK_TETHER_NONE UINT32_MAX
/* CVK_TETHER_ROUNDS (shaders/shared/layout.h): how many times the pass projects a particle
   onto each of its tethers' spheres in turn. */
#include "shared/layout.h"

/* The tethers of every free particle, for the cloths of `scene` that have them, in
   build->tether_anchor (CVK_TETHER_SLOTS internal indices per free particle, nearest first,
   CVK_TETHER_NONE where fewer pins are reachable) and build->tether_length (m, the scaled rest
   distance). Both stay NULL when no cloth has tethers and pins. */
cvk_result cvk_build_tethers(const cvk_scene_desc* scene, cvk_build* build, cvk_error* error);

#endif
