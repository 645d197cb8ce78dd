/* Air on the cloths (cvk_wind_desc, cvk_aero_desc): at the start of each substep one pass
   computes the aerodynamic force on every triangle from the air's velocity relative to it (the
   wind at that time, gusts included, minus the triangle's velocity), its area and its normal;
   a second sums each free particle's share over its triangles in a fixed order (deterministic,
   no float atomics) into h² F / m, which the prediction adds (shaders/solvers/predict.comp, WIND). The
   model (cvk_aero_desc): pressure drag on the normal part of the relative velocity, skin
   friction on the tangential part, and lift across the flow growing as cos θ sin θ, after
   NvCloth's wind (drag and lift coefficients, a force per triangle, a third on each corner).
   A scene without a "wind" block records none of this. */
#ifndef CVK_AERO_H
#define CVK_AERO_H

#include "core/gpu.h"
#include "plan/plan.h"

struct cvk_sim;

typedef struct cvk_aero {
    bool enabled;                /* the scene has a "wind" block */
    cvk_wind_desc wind;
    float* coefficients;         /* 4 per cloth: rho/2 times drag, lift, friction; 0 */
    cvk_buffer triangles;        /* uvec4 per triangle: corners (internal), cloth */
    cvk_buffer coefficient_buffer;
    cvk_buffer forces;           /* vec4 per triangle */
    cvk_buffer incidence;        /* free_count + 1 offsets, then triangle ids */
    cvk_buffer external;         /* vec4 per free particle: h² F / m (16 bytes without wind) */
    VkBufferView view_external;  /* bound by the projective-dynamics set in every scene */
    VkBufferView view_triangles, view_incidence, view_forces;
    cvk_descriptors descriptors;
    bool bound;
} cvk_aero;

/* Resolves the scene's air and makes the tables (a small external buffer alone without wind). */
cvk_result cvk_aero_create(struct cvk_sim* sim, const cvk_scene_desc* scene, cvk_error* error);
void cvk_aero_destroy(struct cvk_sim* sim);

/* Points the passes at the solver's last displacement (a texel view of projective dynamics'
   u[0]). */
void cvk_aero_bind(struct cvk_sim* sim, VkBufferView u);

/* The two passes ("wind"), before the prediction; none without wind. */
cvk_result cvk_aero_add_passes(struct cvk_sim* sim, cvk_plan* plan, cvk_error* error);

/* The wind at time t (s), gusts included, as the device evaluates it (in double). */
void cvk_aero_wind_at(const cvk_wind_desc* wind, double t, double out[3]);

/* The host reference: the air's force on each particle (N, 3 doubles per particle in internal
   order; 0 for pinned ones) at time t from positions x and last displacements u (3 floats per
   particle, internal order), in double precision. */
void cvk_aero_forces_host(const struct cvk_sim* sim, const float* x, const float* u, double t,
                          double* force);

/* The device's last h² F / m per free particle, as forces (N, 3 floats per particle in
   internal order; 0 for pinned ones). */
cvk_result cvk_aero_read_forces(struct cvk_sim* sim, float* force, cvk_error* error);

#endif
