/* Picking (cvk_sim_pick): the nearest particle a ray passes within a radius of, computed on the
   device by shaders/features/pick.comp, outside the frame: a query of its own, recorded, submitted and
   waited for, that leaves the recorded frame as it is. Its objects are made on the first pick. */
#ifndef CVK_PICK_H
#define CVK_PICK_H

#include "core/gpu.h"

typedef struct cvk_pick {
    bool ready;
    cvk_buffer user_of;           /* uint per particle, internal order: its user index */
    cvk_buffer result;            /* host-visible cvk_gpu_pick */
    cvk_descriptors descriptors;  /* one set */
} cvk_pick;

struct cvk_sim;
void cvk_pick_destroy(struct cvk_sim* sim);

#endif
