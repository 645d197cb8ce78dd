/* The state of the families that keep positions and velocities (implicit, explicit): the
   simulation's positions and a velocity buffer (vec4 per particle, w: mass), both in internal
   order, moved through the staging buffer; and the spring adjacency both read. */
#ifndef CVK_VELOCITY_STATE_H
#define CVK_VELOCITY_STATE_H

#include "plan/state.h"

/* Records into `cmd`: positions then `v` -> staging (2 vec4 per particle); v is the
   velocities here, PD's last displacements in lib/solvers/solve_pd.c. */
cvk_result cvk_vstate_record_readback(cvk_sim* sim, VkCommandBuffer cmd, const cvk_buffer* v,
                                      cvk_error* error);
/* Positions and velocities (3 floats per particle, velocity NULL: at rest; pinned particles
   get 0) into the device buffers, masses into v's w. */
cvk_result cvk_vstate_write(cvk_sim* sim, cvk_buffer* v, const float* xyz, const float* velocity,
                            cvk_error* error);
/* Runs the readback `cmd` and copies out positions and velocities (either may be NULL). */
cvk_result cvk_vstate_read(cvk_sim* sim, VkCommandBuffer cmd, float* xyz, float* velocity,
                           cvk_error* error);
/* Uploads the staging buffer's first 2 vec4 per particle into positions and `v`. */
cvk_result cvk_vstate_upload_staged(cvk_sim* sim, cvk_buffer* v, cvk_error* error);
/* The build's adjacency, slot-major: entry s·nf + p = (neighbour, bits of k, bits of L, 0);
   the springs whose flag in `alive` is 0 (torn, lib/features/tear.h; alive NULL: none) with k = 0. */
cvk_result cvk_vstate_upload_adjacency(cvk_sim* sim, cvk_buffer* adjacency, const uint32_t* alive,
                                       cvk_error* error);
/* The end of the family's create, after its buffers and sets: the build's adjacency, the
   state at rest at the build's positions, and `readback_cmd` recorded to read positions and
   `v` back. */
cvk_result cvk_vstate_start(cvk_sim* sim, cvk_buffer* v, cvk_buffer* adjacency,
                            VkCommandBuffer readback_cmd, cvk_error* error);
/* Snapshots begin with positions[n] vec4 then v[n] vec4, exactly as held (32 n bytes):
   copied into `data` through `readback_cmd`, and back from it. */
cvk_result cvk_vstate_save(cvk_sim* sim, VkCommandBuffer readback_cmd, void* data,
                           cvk_error* error);
cvk_result cvk_vstate_load(cvk_sim* sim, cvk_buffer* v, const void* data, cvk_error* error);
/* set_torn of the implicit and explicit families (solver.h): the spring flags, and
   `adjacency` as cvk_vstate_upload_adjacency makes it. */
cvk_result cvk_vstate_set_torn(cvk_sim* sim, cvk_buffer* adjacency, const uint32_t* alive,
                               cvk_error* error);

#endif
