/* The other split of a quad: where the spring along the diagonal a grid cell (or a mesh
   file's quad) is split along has torn while the spring along its other diagonal holds, the
   drawn mesh and the export split the quad along that other diagonal, so a cut running across
   the split diagonals follows the diagonals the cloth still holds instead of stepping around
   whole cells. The simulation does not use it (its springs are the same either way). */
#ifndef CVK_SPLIT_H
#define CVK_SPLIT_H

#include <stdbool.h>
#include <stdint.h>

#include "core/error.h"
#include "sim/sim.h"

/* Per build triangle: `across` is UINT32_MAX where it has no other split; otherwise the
   triangle drawn in its place (vertices in user order, the spring along each edge from
   vertex e to e + 1), the spring along the quad's split diagonal and the one across. */
typedef struct cvk_other_split {
    uint32_t vertices[3];
    uint32_t springs[3];
    uint32_t split, across;
} cvk_other_split;

/* The other splits of the simulation's triangles: two triangles (o0, p, q) and (o1, q, p)
   on one edge whose spring is a shear spring that may tear, with a shear spring across
   o0 − o1, become (o0, p, o1) and (o0, o1, q). *out NULL (and success) where no triangle has
   one (no tearing, no shear springs); else triangle_count entries the caller frees. */
cvk_result cvk_other_splits(const cvk_sim* s, cvk_other_split** out, cvk_error* error);

/* Whether triangle t is drawn from its other split under the spring flags `alive`. */
static inline bool cvk_split_taken(const cvk_other_split* o, const uint32_t* alive)
{
    return o->across != UINT32_MAX && alive && !alive[o->split] && alive[o->across];
}

#endif
