/* Private scene interface: validation that keeps the key path apart from the problem, so the
   JSON loader can put the file name and "(from --set)" around the path. */
#ifndef CVK_SCENE_H
#define CVK_SCENE_H

#include "clothvk.h"
#include "scene/check.h"
#include "shared/layout.h"

/* What a simulation's step reads of its scene, derived once (cvk_step_params_of): the one
   copy every module reads. */
typedef struct cvk_step_params {
    float dt;          /* substep length h, s */
    uint32_t substeps; /* substeps per frame */
    bool integrate;    /* false: no inertia or gravity */
    float gravity[3];  /* m/s² */
    float damping;     /* fraction of velocity removed per substep */
    bool contact;      /* the scene has colliders or self-contact */
} cvk_step_params;

cvk_step_params cvk_step_params_of(const cvk_scene_desc* scene);

/* true when desc is valid; otherwise fills issue with the first problem found. */
bool cvk_scene_desc_check(const cvk_scene_desc* desc, cvk_scene_issue* issue);

/* CVK_ERROR_INVALID_ARGUMENT with "path: problem" (or the problem alone without a path). */
cvk_result cvk_fail_issue(cvk_error* error, const cvk_scene_issue* issue);

/* The solver part of cvk_scene_desc_check, for cvk_sim_set_solver; paths start "solver.". */
bool cvk_solver_desc_check(const cvk_solver_desc* solver, cvk_scene_issue* issue);
/* The same for a render description alone; paths start with "render.". */
bool cvk_render_desc_check(const cvk_render_desc* desc, cvk_scene_issue* issue);

/* Attachments (lib/scene/scene_attach.c): each names a cloth of the scene, attaches at least one
   particle by pins valid for that cloth, and moves by a valid motion; and the solver moves them
   (cvk_attachments_solver_check, also for cvk_sim_set_solver). */
bool cvk_attachments_check(const cvk_scene_desc* desc, cvk_scene_issue* issue);
bool cvk_attachments_solver_check(const cvk_solver_desc* solver, uint32_t attachment_count,
                                  cvk_scene_issue* issue);

/* Air (lib/scene/scene_air.c): the wind block and air_density, and the solver it needs; a cloth's
   aero coefficients (paths start with base). */
bool cvk_wind_check(const cvk_scene_desc* desc, cvk_scene_issue* issue);
bool cvk_wind_solver_check(const cvk_solver_desc* solver, bool wind, cvk_scene_issue* issue);
bool cvk_aero_check(const cvk_aero_desc* aero, const char* base, cvk_scene_issue* issue);
/* How a cloth is drawn (lib/scene/scene_look.c): its material block's back_color, sheen,
   roughness, thickness, normal_map and normal_strength (paths start with base). */
bool cvk_look_check(const cvk_cloth_desc* cloth, const char* base, cvk_scene_issue* issue);
/* How a collider is drawn (the same file): its color and its material block's roughness,
   texture (not empty) and texture_scale (> 0). */
bool cvk_collider_look_check(const cvk_collider_desc* collider, const char* base, cvk_scene_issue* issue);

/* render.fit: its margin in [0, 0.45], no keyframed camera, render.eye and render.target both
   or neither (lib/scene/scene_look.c). */
bool cvk_fit_check(const cvk_render_desc* r, cvk_scene_issue* issue);
/* Collision (lib/scene/scene_collision.c): the collision block's keys; a given radius against
   a thickness (the scene's, or the default the simulation resolved when the scene gives none);
   the radius a thickness resolves to (0: 1.3 thicknesses); and one sentence for each key of
   an earlier contact the block sets, which has no effect (static strings; returns how many). */
#define CVK_COLLISION_NOTES_MAX 3u
bool cvk_collision_check(const cvk_collision_desc* collision, cvk_scene_issue* issue);
bool cvk_collision_radius_check(const cvk_collision_desc* collision, float thickness,
                                cvk_scene_issue* issue);
float cvk_collision_radius(const cvk_collision_desc* collision, float thickness);
uint32_t cvk_collision_detection_interval(const cvk_collision_desc* collision); /* 0 is 1 */
/* The contact radius by default: this many thicknesses — 8 % less than a grid cloth's nearest
   rest distance from a particle to a feature not around it (its parallel diagonals, about 1.41
   default thicknesses apart), so a flat cloth lists no pairs of its own, nor a cloth compressed
   by a few percent as it folds (with 1.4 the 40 x 40 drape listed its diagonals, and its
   contact pass took 13.6 ms a frame instead of 6.4). */
#define CVK_RADIUS_THICKNESSES 1.3f
uint32_t cvk_collision_notes(const cvk_collision_desc* collision,
                             const char* notes[CVK_COLLISION_NOTES_MAX]);
/* Tearing (lib/scene/scene_tear.c): each cloth's max_stretch, and tearing apart from tethers. */
bool cvk_tearing_check(const cvk_scene_desc* desc, cvk_scene_issue* issue);
/* Whether some cloth of the scene tears. */
bool cvk_scene_tears(const cvk_scene_desc* desc);
/* Bit t set: the scene has a collider of type t (cvk_collider_type). */
uint32_t cvk_scene_collider_types(const cvk_scene_desc* desc);
/* Largest tearing max_stretch: the divergence watch stops a solve whose spring reaches ten
   times its rest length (CVK_DIVERGED_STRETCH in lib/sim/sim.h), a stretch of 9. */
#define CVK_MAX_TEAR_STRETCH 9.0

/* Fastest mean wind, m/s: ten times a hurricane's; a typo is refused. */
#define CVK_MAX_WIND 700.0

/* The cloth description whose pins are the attachment's (the rest is the cloth's): the pins
   checks and the topology's pin selection then serve attachments too. */
cvk_cloth_desc cvk_attachment_pins_as_cloth(const cvk_cloth_desc* cloth,
                                            const cvk_attachment_desc* attachment);

/* Bounds on the counts whose products size the step plan and the frame a command buffer
   records (a typo such as "substeps": 4294967295 must be refused, not recorded until memory
   runs out), and on dt, whose 1/dt² must fit single precision. */
#define CVK_MAX_SUBSTEPS 10000u
#define CVK_MAX_SWEEPS 10000u          /* outer × inner iterations per substep */
#define CVK_MAX_FRAME_DISPATCHES 1000000u
#define CVK_MIN_DT 1e-6
#define CVK_MAX_SCENE_BYTES (64u << 20) /* a scene file's size */
/* A mesh file's size: Assimp holds the whole file and its own copy of every vertex and face,
   several times the file; 1 GiB of text is some 30 million triangles, beyond what one
   scene's device buffers hold (CVK_MAX_PARTICLES, and the device's own limits before that). */
#define CVK_MAX_MESH_BYTES (UINT64_C(1) << 30)

/* Most copies an "instances" block makes, and most cloths its copies hold together: a million
   cloths are a million descriptions on the host before the device is asked (whose own limits,
   checked at creation, come first for anything but the smallest cloths). */
#define CVK_MAX_INSTANCES (1u << 20)

/* Most particles one scene may hold, over all its cloths. */
#define CVK_MAX_PARTICLES (UINT64_C(1) << 30)

/* Bounds on what sizes the device's collider buffers (one record per collider, its keyframes
   uploaded whole and searched per substep), so that a typo in a count is refused up front: a
   particle meets only its own instance's colliders, so their number costs memory, not time;
   10000 keyframes is almost three minutes at 60 keyframes a second. */
#define CVK_MAX_COLLIDERS (1u << 20) /* as many as CVK_MAX_INSTANCES copies of one; the device's
                                        storage buffers may hold fewer (checked at creation) */

/* Largest tether scale: a tether ten times its rest distance no longer holds anything. */
#define CVK_MAX_TETHER_SCALE 10.0

/* Fastest initial cloth velocity, m/s: ten times a rifle bullet. At that speed a particle
   crosses 10 m in a 1 ms substep and is 10 km away after a second, where single-precision
   positions are a millimetre apart; no cloth scene needs more, and a typo is refused rather
   than simulated into nonsense. */
#define CVK_MAX_VELOCITY 1e4

#endif
