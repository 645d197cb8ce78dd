/* clothvk — cloth simulation as Vulkan compute work.
 *
 * Step by step
 * ------------
 * 1. Make a context. Either the library creates a headless Vulkan instance and device
 *    (the first device, or the one $CLOTHVK_DEVICE names by index or name substring):
 *
 *        cvk_error err;
 *        cvk_context* ctx;
 *        if (cvk_context_create(&(cvk_context_desc){0}, &ctx, &err) != CVK_SUCCESS)
 *            fprintf(stderr, "%s\n", err.message);
 *
 *    or it adopts yours: fill instance, physical_device, device, queue_family and queue in
 *    cvk_context_desc. The library never destroys what it adopted.
 *
 * 2. Describe a scene, in code or from a JSON file (format in README.md):
 *
 *        cvk_cloth_desc cloth = cvk_default_cloth_desc();
 *        cloth.grid[0] = 64; cloth.grid[1] = 64;
 *        cvk_scene_desc scene = cvk_default_scene_desc();
 *        scene.cloths = &cloth; scene.cloth_count = 1;
 *
 *    or   cvk_scene* file; cvk_scene_load("hanging.json", NULL, 0, &file, &err);
 *         const cvk_scene_desc* scene = cvk_scene_get_desc(file);
 *
 * 3. Create a simulation and advance it. Either record its frames into your own command
 *    buffer (nothing is submitted and nothing waits inside), or call the blocking step:
 *
 *        cvk_sim* sim;
 *        cvk_sim_create(ctx, &(cvk_sim_desc){ .scene = &scene }, &sim, &err);
 *        cvk_sim_record(sim, my_cmd, 1, &err);   // one frame per submission of my_cmd
 *        cvk_sim_step(sim, 10, &err);            // or: ten frames, submitted and waited for
 *
 * 4. Read the particles back (cloth by cloth: grids row by row, meshes in file order), or
 *    the whole mesh with cvk_sim_read_mesh, and ask for statistics: residual, stretch, NaN
 *    count, GPU time per pass. Let a user pull the cloth: cvk_sim_pick finds the particle
 *    under a ray (a click), cvk_sim_grab drags it to where the mouse goes, frame after frame,
 *    cvk_sim_release lets go (examples/drag.c).
 *
 * 5. See it. A mesh turns the particles into triangles and normals on the device, every
 *    frame, with no trip through the host. Either clothvk draws it (shadow-mapped, two lights,
 *    multisampled, sRGB) and hands you the pixels:
 *
 *        cvk_mesh* mesh;
 *        cvk_mesh_create(sim, NULL, &mesh, &err);
 *        cvk_renderer* renderer;
 *        cvk_renderer_create(mesh, &scene.render, &renderer, &err);
 *        cvk_renderer_draw(renderer, &err);     // or cvk_renderer_record into your buffer
 *        cvk_image image = cvk_renderer_get_image(renderer);
 *        cvk_image_write_png(&image, "frame.png", &err);
 *
 *    or you draw it with your own pipeline: cvk_mesh_record into your command buffer, one
 *    barrier (see cvk_mesh_record), then bind the buffers of cvk_mesh_get_buffers.
 *    examples/embed.c is a complete program that does that.
 *
 * 6. Destroy in reverse order: cvk_renderer_destroy, cvk_mesh_destroy, cvk_sim_destroy,
 *    cvk_scene_destroy, cvk_context_destroy.
 *
 * Rules that hold everywhere
 * - Every fallible call returns a cvk_result; on failure the optional cvk_error receives the
 *   same code and one sentence naming the cause (the JSON key path, the Vulkan call and its
 *   VkResult, the device limit). The library never prints, exits or aborts.
 * - No global state: objects are independent; one object must not be used from two threads
 *   at once.
 * - Descriptions are plain structs: start from cvk_default_*_desc() (or zero where the struct
 *   says zero means default) and change what you need.
 */
#ifndef CLOTHVK_H
#define CLOTHVK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32) && defined(CLOTHVK_BUILD_SHARED)
#define CVK_API __declspec(dllexport)
#elif defined(__GNUC__)
#define CVK_API __attribute__((visibility("default")))
#else
#define CVK_API
#endif

#define CLOTHVK_VERSION_MAJOR 0
#define CLOTHVK_VERSION_MINOR 1
#define CLOTHVK_VERSION_PATCH 0

/* ----------------------------------------------------------------------------------------
 * Results and errors
 * ------------------------------------------------------------------------------------- */

typedef enum cvk_result {
    CVK_SUCCESS = 0,
    CVK_ERROR_INVALID_ARGUMENT, /* a description or argument is wrong; the message names it */
    CVK_ERROR_IO,               /* a file could not be read or written */
    CVK_ERROR_PARSE,            /* scene text is not well-formed JSON (line and column given) */
    CVK_ERROR_UNSUPPORTED,      /* the device or this configuration lacks what is needed */
    CVK_ERROR_DEVICE_LIMIT,     /* the scene exceeds a limit of the device */
    CVK_ERROR_OUT_OF_MEMORY,    /* host or device memory ran out */
    CVK_ERROR_VULKAN,           /* a Vulkan call failed; the message names it and its VkResult */
    CVK_ERROR_DIVERGED,         /* the simulation blew up; the message names the frame and cloth */
    CVK_ERROR_DEVICE_LOST,      /* the device was lost (VK_ERROR_DEVICE_LOST): objects made on its
                                   context can only be destroyed; nothing more is submitted */
} cvk_result;

/* One sentence that says why a call failed. Pass NULL where you do not want it. */
typedef struct cvk_error {
    cvk_result result;
    char message[512];
} cvk_error;

/* "CVK_ERROR_PARSE" and so on. */
CVK_API const char* cvk_result_name(cvk_result result);

/* The library's version, "MAJOR.MINOR.PATCH" as in CLOTHVK_VERSION_*: the one it was built as. */
CVK_API const char* cvk_version(void);

/* ----------------------------------------------------------------------------------------
 * Context: the Vulkan instance, device and queue the library works with
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_context cvk_context;

/* Receives each validation-layer message (warnings and errors) while validation is on. */
typedef void (*cvk_log_fn)(void* user, const char* message);

/* Zero means default for every field. */
typedef struct cvk_context_desc {
    /* Khronos validation layer: 0 = on when $CLOTHVK_VALIDATION is "1", 1 = on, -1 = off.
       Ignored when adopting (enable the layer on your own instance). */
    int validation;
    /* Device to use: an index ("1") or a substring of the device name ("llvmpipe").
       NULL: $CLOTHVK_DEVICE, else the first device. Ignored when adopting. */
    const char* device_name;
    /* Called for every validation message; may be NULL (messages are still counted). */
    cvk_log_fn log;
    void* log_user;

    /* Adoption: set instance, physical_device, device and queue (queue_family is read only
       then; 0 is a valid family) to use the application's objects. The queue family must
       support compute; timestamps are used when it supports them. The library submits to
       that queue (and waits for it) in cvk_sim_step, cvk_sim_get_stats, the read, write and
       set calls, cvk_sim_pick, a simulation's first cvk_sim_grab, cvk_mesh_create,
       cvk_renderer_create and cvk_renderer_draw, and waits for it in every destroy call: like any Vulkan queue it must not be used from another thread
       at the same time. */
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
} cvk_context_desc;

CVK_API cvk_result cvk_context_create(const cvk_context_desc* desc, cvk_context** out_context,
                              cvk_error* error);
CVK_API void cvk_context_destroy(cvk_context* context);

/* What the library found out about its device. */
typedef struct cvk_context_info {
    const char* device_name;      /* e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" */
    uint32_t api_version;         /* VK_MAKE_API_VERSION of the device */
    bool adopted;                 /* true when the application's device is used */
    bool validation;              /* true when the validation layer is on */
    bool timestamps;              /* true when GPU pass times can be measured */
    uint32_t subgroup_size;       /* informative only; the kernels do not depend on it */
    uint64_t max_particles;       /* largest particle count the device's buffer limits allow */
    bool graphics;                /* true when the queue can draw: the renderer needs it */
    uint32_t max_image_size;      /* largest image width and height the renderer can make */
    uint64_t device_bytes;        /* device memory held now by everything made on this context */
    uint64_t device_peak_bytes;   /* the most it has held at once */
} cvk_context_info;

CVK_API cvk_context_info cvk_context_get_info(const cvk_context* context);

/* Validation messages (warnings and errors) received so far; tests fail when non-zero. */
CVK_API uint32_t cvk_context_validation_message_count(const cvk_context* context);

/* ----------------------------------------------------------------------------------------
 * Scene description
 * ------------------------------------------------------------------------------------- */

typedef enum cvk_method {
    CVK_METHOD_PD = 0, /* projective dynamics (Liu et al. 2013), Verlet prediction */
    CVK_METHOD_IMPLICIT, /* backward Euler, one linearised Newton step per substep (Baraff & Witkin);
                            colliders as filtered constraints, no self-contact */
    CVK_METHOD_EXPLICIT, /* explicit mass-spring integration (seed 001): euler, rk2, adams-bashforth, verlet */
} cvk_method;

/* The explicit method's integrator; NONE (the default) is euler for explicit and the only value
   the other methods take. */
typedef enum cvk_integrator {
    CVK_INTEGRATOR_NONE = 0,
    CVK_INTEGRATOR_EULER,      /* forward Euler: v += h a(x, v), x += h v (the old v) */
    CVK_INTEGRATOR_RK2,        /* second-order TVD Runge-Kutta (Shu-Osher) */
    CVK_INTEGRATOR_AB4,        /* fourth-order Adams-Bashforth, euler for its first 3 steps */
    CVK_INTEGRATOR_VERLET,     /* position Verlet, velocity (x_n - x_n-1) / h */
} cvk_integrator;

/* How the explicit method damps; NONE (the default) is spring for explicit. */
typedef enum cvk_damping_model {
    CVK_DAMPING_NONE = 0,
    CVK_DAMPING_SPRING,        /* -kd ((v_a - v_b).n) n along each spring (Matyka) */
    CVK_DAMPING_VISCOSITY,     /* -kd (v_a - v_b) across each spring (artificial viscosity, Desbrun) */
} cvk_damping_model;

typedef enum cvk_linear_solver {
    CVK_LINEAR_RBGS = 0,   /* multi-colour Gauss-Seidel on the GPU, SOR with omega */
    CVK_LINEAR_JACOBI,     /* Jacobi on the GPU, relaxation omega */
    CVK_LINEAR_CHEBYSHEV,  /* Jacobi with Chebyshev semi-iterative acceleration (Wang 2015) */
    CVK_LINEAR_GS_CPU,     /* sequential double-precision Gauss-Seidel on the host (reference) */
    CVK_LINEAR_CG,         /* filtered block-Jacobi preconditioned conjugate gradient (implicit) */
} cvk_linear_solver;

typedef struct cvk_solver_desc {
    cvk_method method;          /* CVK_METHOD_PD */
    cvk_linear_solver linear;   /* usually CVK_LINEAR_RBGS */
    uint32_t outer_iterations;  /* local/global alternations per substep, usually 4 */
    uint32_t inner_iterations;  /* linear sweeps per outer iteration, usually 4 */
    float omega;                /* SOR factor (rbgs, gs-cpu) or relaxation (jacobi, chebyshev), 0 < omega < 2, usually 1 */
    float chebyshev_rho;        /* spectral radius for chebyshev; 0 = estimated at build time */
    uint32_t chebyshev_delay;   /* plain sweeps before Chebyshev weights start, usually 2 */
    float tolerance;            /* where the solve stops, 0 ≤ tolerance < 1; 0 = the method's default.
                                   implicit: relative residual of cg / jacobi, default 1e-3. pd
                                   (rbgs, jacobi, chebyshev): |D⁻¹(b − A u)| / the same at the
                                   substep's first iterate (D⁻¹(b − A u): the move one Jacobi
                                   sweep would make), checked on the device at the start of
                                   every outer iteration; default none (every sweep runs) */
    uint32_t max_iterations;    /* sweeps per substep, at most; 0 = the method's default. implicit:
                                   cg iterations or jacobi sweeps, default 100. pd: a multiple of
                                   inner_iterations that replaces outer × inner (its default) */
    float kd;                   /* implicit, explicit: spring damping (or viscosity), N·s/m; usually 0 */
    cvk_integrator integrator;  /* explicit: CVK_INTEGRATOR_NONE = euler */
    cvk_damping_model damping_model; /* explicit: CVK_DAMPING_NONE = spring */
    uint32_t tether_every;      /* pd with tethers: the tether pass after every this many outer
                                   iterations and after the last; 0 or 1 = after each (the
                                   default); 2 halves the pass's cost for a little stretch */
} cvk_solver_desc;

typedef struct cvk_stiffness {
    float structural; /* N/m along grid rows and columns, or mesh edges; 0 = absent; usually 1e6 */
    float shear;      /* N/m across grid cells and quad faces (both diagonals); 0 = absent */
    float bend;       /* N/m to grid second neighbours (i±2, j), (i, j±2), or across mesh edges;
                         0 = absent */
} cvk_stiffness;

/* Scale, then rotation, then translation: x' = translation + rotation (scale ⊙ x). */
typedef struct cvk_transform {
    float scale[3];              /* per axis; usually [1, 1, 1] */
    float rotation[4];           /* quaternion [w, x, y, z], normalised by the library; usually
                                    [1, 0, 0, 0] */
    float translation[3];        /* m; usually [0, 0, 0] */
} cvk_transform;

/* An axis-aligned box, min then max corner, m. */
typedef struct cvk_box3 {
    float min[3];
    float max[3];
} cvk_box3;

/* Aerodynamic coefficients of a cloth's triangles (used when the scene has a "wind" block). A
   triangle of area A, unit normal n, in air moving at v relative to it (|v| = speed, the
   normal part v_n = (v·n) n, the tangential v_t = v − v_n, cos θ = v·n / |v|) feels
   ½ ρ A (drag |v·n| v_n + friction |v| v_t + lift cos θ sin θ |v|² l), l the unit vector across
   v in the plane of v and n (after NvCloth's wind); a third of it on each corner. */
typedef struct cvk_aero_desc {
    float drag;                  /* pressure drag along the normal, ≥ 0; usually 1 */
    float lift;                  /* lift across the flow, ≥ 0; usually 0.2 */
    float friction;              /* skin friction along the surface, ≥ 0; usually 0.02 */
} cvk_aero_desc;

/* Tearing (the "tearing" block of a cloth): a spring of the cloth whose relative stretch
   |xa − xb| / L − 1 passes max_stretch at the end of a substep breaks for good. It then pulls
   no more in the solve, and the triangles along it leave the mesh, the renderer and the
   exports. Decided spring by spring, each on its own, so the same springs break on every
   run and dispatch shape. Every solver tears (gs-cpu on the host); tethers refuse it. */
typedef struct cvk_tearing_desc {
    float max_stretch;           /* relative stretch at which a spring breaks; 0 = never (the
                                    default); e.g. 0.5 breaks a spring at 1.5 × its rest length */
} cvk_tearing_desc;

/* One cloth: a rectangular grid of particles (the default) or a triangle mesh read from a file.

   Grid: particle [i, j] sits at origin + i·du·u_axis + j·dv·v_axis, du = size[0] / (grid[0] − 1),
   dv = size[1] / (grid[1] − 1). A 1×N grid is a rope. Structural springs join (i±1, j) and
   (i, j±1), shear springs the cell diagonals, bend springs (i±2, j) and (i, j±2).

   Mesh (mesh != NULL): every vertex of the file is a particle; vertices the file repeats only
   for UVs or normals are welded by position. Structural springs lie on every edge of the file's
   faces, shear springs across both diagonals of every quad face, bend springs across every
   interior edge between the two vertices opposite it (in the triangles the faces are split
   into). Rest lengths come from the file (after the transform), times rest_scale. Particles
   are in file order: welded vertices once, in order of first appearance. */
typedef struct cvk_cloth_desc {
    const char* name;            /* for messages and output; may be NULL */
    uint32_t grid[2];            /* particles along u and v, each ≥ 1; usually [100, 100] */
    float size[2];               /* metres along u and v; usually [1, 1] */
    float origin[3];             /* position of particle [0, 0], m */
    float u_axis[3];             /* direction of increasing i (normalised by the library) */
    float v_axis[3];             /* direction of increasing j (normalised by the library) */
    const char* mesh;            /* triangle or quad mesh file (OBJ, glTF 2, PLY, STL), read
                                    through Assimp; NULL = a grid. A scene file's relative path
                                    is relative to the scene file; in code, to the working
                                    directory. grid, size, origin and the axes are then unused */
    cvk_transform transform;     /* applied to the mesh's vertices; unused for grids */
    float rest_scale;            /* rest length = spacing · rest_scale; 0.2 stretches ×5 */
    float mass;                  /* kg for the whole cloth; > 0, usually 0.1. A grid spreads it
                                    evenly, a mesh by the area around each vertex */
    float density;               /* kg/m², areal density; > 0 replaces mass: each particle gets
                                    a third of the area of its triangles times density. 0 = use
                                    mass (the default) */
    cvk_stiffness stiffness;     /* N/m per spring kind */
    const uint32_t (*pins)[2];   /* grids: grid coordinates [i, j] held in place */
    uint32_t pin_count;
    const uint32_t* pin_vertices;/* meshes: vertex indices (particle order, above) held in place */
    uint32_t pin_vertex_count;
    bool use_pin_box;            /* true: also pin every particle inside pin_box */
    cvk_box3 pin_box;            /* m, after the transform; min ≤ max on every axis */
    float color[3];              /* linear RGB in [0, 1], for renderers */
    const char* texture;         /* image file (PNG, JPEG, ...; stb_image) drawn on the cloth in
                                    place of color, its 8-bit values sRGB; NULL = none. A scene
                                    file's relative path is relative to the scene file. Read by
                                    cvk_renderer_create, mapped by the mesh file's texture
                                    coordinates, or on a grid by u = i / (grid[0] − 1) ·
                                    texture_scale[0], v = j / (grid[1] − 1) · texture_scale[1] */
    float texture_scale[2];      /* grids: repeats of the texture along u and v; > 0, usually
                                    [1, 1]; unused for meshes */
    float velocity[3];           /* initial velocity of every free particle, m/s; usually 0 */
    float tethers;               /* long-range attachments: 0 = none (the default); ≥ 1: no
                                    free particle gets farther from any of its (up to) four
                                    nearest pins than tethers × its rest distance to it across
                                    the cloth; usually 1. A cloth without pins has none.
                                    Projective dynamics only */
    cvk_aero_desc aero;          /* how the air of cvk_scene_desc.wind pushes it */
    cvk_tearing_desc tearing;    /* when its springs break; none by default */
    uint32_t cookie_;            /* set by cvk_default_cloth_desc; do not touch */
} cvk_cloth_desc;

/* ----------------------------------------------------------------------------------------
 * Motion over time: keyframes (colliders now; attachments and cameras use the same format)
 * ------------------------------------------------------------------------------------- */

/* A rigid pose at a time: a point p of the object as described moves to
   translation + rotation · p (rotation about the world origin, then translation). */
typedef struct cvk_keyframe {
    float time;                  /* s, ≥ 0; strictly increasing along the list */
    float translation[3];        /* m; usually [0, 0, 0] */
    float rotation[4];           /* quaternion [w, x, y, z], normalised by the library; usually
                                    [1, 0, 0, 0] */
} cvk_keyframe;

/* Keyframed motion: translation interpolated linearly, rotation by slerp (the shorter way),
   held at the first keyframe before it and at the last after it; with loop the motion repeats
   with period last.time − first.time (time before the first keyframe is still held). No
   keyframes: the identity pose at every time. */
typedef struct cvk_motion {
    const cvk_keyframe* keyframes;
    uint32_t keyframe_count;
    bool loop;
} cvk_motion;

/* Kinematic particles of one cloth moved by keyframes (the curtain rail of seed 002 fig. 6.20):
   a chosen particle at p when the simulation is created is at translation(t) + rotation(t) · p
   at time t, so keyframes that start at the identity pose start from where the particles are.
   Attached particles are pinned (infinitely heavy) for the solver; the recorded work computes
   their positions from the frame state on the device, and each substep's displacement is the
   motion's, so the cloth is dragged, not teleported. The particles are those of pins,
   pin_vertices and pin_box together (at least one); no particle may be in two attachments.
   The projective-dynamics solvers on the device (rbgs, jacobi, chebyshev) move them; implicit
   and gs-cpu refuse a scene with attachments. */
typedef struct cvk_attachment_desc {
    uint32_t cloth;              /* index into cvk_scene_desc.cloths */
    const uint32_t (*pins)[2];   /* grids: grid coordinates [i, j] */
    uint32_t pin_count;
    const uint32_t* pin_vertices;/* meshes: vertex indices (particle order) */
    uint32_t pin_vertex_count;
    bool use_pin_box;            /* true: also every particle of the cloth inside pin_box */
    cvk_box3 pin_box;            /* m, at the start; min ≤ max on every axis */
    cvk_motion motion;           /* no keyframes: held where it starts */
} cvk_attachment_desc;

/* ----------------------------------------------------------------------------------------
 * Collisions
 * ------------------------------------------------------------------------------------- */

/* Contact between cloths (self- and cloth-cloth) and the defaults of every collider. */
typedef struct cvk_collision_desc {
    bool self;                   /* particle–triangle contact between and within cloths;
                                    usually false */
    float thickness;             /* m: the distance kept between a particle and any surface
                                    (collider or cloth); 0 = half the shortest rest length of
                                    any structural spring (the default) */
    float friction;              /* Coulomb kinetic coefficient, ≥ 0; usually 0.3 */
    float static_friction;       /* static coefficient, ≥ friction; usually 0.4 */
    uint32_t detect_every;       /* 0 (the default): search for cloth-contact candidates (the
                                    hash and the query) only at substeps that start with some
                                    particle a quarter thickness from where the last search saw
                                    it — as safe as searching every substep, and free for a
                                    cloth at rest; k (1 to substeps): every k substeps whatever
                                    moved (k > 1 is cheaper, but layers approaching faster than
                                    about a thickness per k substeps may pass through) */
    float exclusion;             /* m: a particle is never in contact with a triangle of its
                                    own cloth that had a corner within this distance of it at
                                    rest; 0 = 1.5 thicknesses (the default: in a grid, only the
                                    particle's own triangles, so folds one particle wide are
                                    held apart). Past the detection radius plus the longest
                                    edge a flat cloth has no candidates and the search is several
                                    times cheaper, but folds tighter than the exclusion can pass
                                    through themselves: for cloths with bending stiffness */
    bool edges;                  /* with self: edge–edge contact too, keeping the cloths' edges
                                    a thickness apart where they pass each other with no
                                    particle near a face (narrow strips crossing, a fold's
                                    crease across a border); a wider search. Usually false */
} cvk_collision_desc;

typedef enum cvk_collider_type {
    CVK_COLLIDER_PLANE = 0,      /* point, normal: everything below the plane is solid */
    CVK_COLLIDER_SPHERE,         /* center, radius */
    CVK_COLLIDER_BOX,            /* center, half_extents, rotation */
    CVK_COLLIDER_CAPSULE,        /* a, b, radius: the points within radius of segment ab */
    CVK_COLLIDER_FUNNEL,         /* apex, funnel_a, height: a thin surface of revolution */
    CVK_COLLIDER_MESH,           /* file, transform: a closed triangle mesh (signed distance) */
    CVK_COLLIDER_TYPE_COUNT
} cvk_collider_type;

/* One rigid collider. Shape fields are in scene coordinates at rest; motion moves the whole
   shape rigidly (a point p of it is at translation(t) + rotation(t) · p at time t), and the
   surface's velocity enters friction (pd) and the held particles' velocity (implicit).

   Funnel: seed 002's parametric surface x = u cos v, y = a ln u, z = u sin v around the world
   up axis (+y) with its origin at apex (where the radius is 1 m), from apex down to `height`
   below it: radius e^(y/a) for −height ≤ y ≤ 0 (relative to apex). Cloth keeps to the side
   of the surface it is on. */
typedef struct cvk_collider_desc {
    cvk_collider_type type;
    const char* name;            /* for messages and output; may be NULL */
    float point[3];              /* plane: a point on it, m */
    float normal[3];             /* plane: towards the free side (normalised by the library) */
    float center[3];             /* sphere, box: m */
    float radius;                /* sphere, capsule: m, > 0 */
    float half_extents[3];       /* box: m, each > 0 */
    float rotation[4];           /* box: quaternion [w, x, y, z]; usually [1, 0, 0, 0] */
    float a[3], b[3];            /* capsule: segment ends, m */
    float apex[3];               /* funnel: m */
    float funnel_a;              /* funnel: growth length a, m, > 0 */
    float height;                /* funnel: m, > 0 */
    const char* file;            /* mesh: triangle mesh file (as cvk_cloth_desc.mesh), closed */
    cvk_transform transform;     /* mesh: applied to the file's vertices */
    float friction;              /* < 0: collision.friction (the default) */
    float static_friction;       /* < 0: collision.static_friction (the default) */
    cvk_motion motion;           /* no keyframes: static */
    float color[3];              /* linear RGB for renderers; usually [0.55, 0.55, 0.6] */
    uint32_t cookie_;            /* set by cvk_default_collider_desc; do not touch */
} cvk_collider_desc;

/* A directional light: parallel rays, like the sun. */
typedef struct cvk_light {
    float direction[3];          /* from the scene towards the light (normalised by the library) */
    float color[3];              /* linear RGB intensity; [1, 1, 1] is full white */
} cvk_light;

/* The camera at a time (render.camera_keyframes): between keyframes the eye and the target move
   in straight lines, held before the first keyframe and after the last; with camera_loop the
   path repeats (the rules of cvk_motion's translation). */
typedef struct cvk_camera_keyframe {
    float time;                  /* s, ≥ 0; strictly increasing along the list */
    float eye[3];                /* camera position, m */
    float target[3];             /* point the camera looks at, m; not the eye */
} cvk_camera_keyframe;

/* How the renderer sees the scene: the "render" block of a scene file. The defaults frame the
   scene's reach (where its cloths can go: their starting box and, below their pins, how far
   they can hang) from the front, above and to the right, lit by a key light from above. */
typedef struct cvk_render_desc {
    uint32_t size[2];            /* image width and height in pixels; usually [1280, 720] */
    bool auto_eye;               /* true: the eye is placed so that the reach fills the view;
                                    false: eye below. Usually true */
    float eye[3];                /* camera position, m */
    bool auto_target;            /* true: the camera looks at the middle of the reach; usually true */
    float target[3];             /* point the camera looks at, m */
    float up[3];                 /* camera up and ground normal (normalised); usually [0, 1, 0] */
    float fov_y;                 /* vertical field of view, degrees, in (0, 180); usually 35 */
    cvk_light key;               /* casts the shadows */
    cvk_light fill;              /* softer, no shadows: keeps the key light's dark side readable */
    float ambient[3];            /* linear RGB light from everywhere */
    float background[3];         /* linear RGB of the sky behind the scene */
    bool ground;                 /* draw a ground plane that receives shadows; usually true */
    bool auto_ground_height;     /* true: just below the reach; usually true */
    float ground_height;         /* m along up (the plane is {x : x · up = ground_height}) */
    float ground_color[3];       /* linear RGB */
    uint32_t shadow_map_size;    /* texels per side of the key light's depth map, 16 to 16384;
                                    usually 2048 */
    uint32_t samples;            /* multisampling: 1, 2, 4 or 8 samples per pixel, usually 4 */
    bool wireframe;              /* draw the triangle edges over the shaded cloth; usually false */
    const cvk_camera_keyframe* camera_keyframes; /* a moving camera (eye and target above are then
                                    unused); usually none */
    uint32_t camera_keyframe_count;
    bool camera_loop;            /* repeat the camera's path, period last.time − first.time */
} cvk_render_desc;

/* Gusts: the wind's speed and direction varying with simulated time t, deterministically
   (the same on every run and on the device and host): with phase τ = 2π t / period,
   speed factor 1 + amplitude · (sin τ + sin(1.618 τ + 1)) / 2 and a turn about the up axis
   (+y) by jitter · sin(0.73 τ + 2) degrees. */
typedef struct cvk_gusts_desc {
    float amplitude;             /* fraction of the mean speed the gusts add or take, 0 to 1;
                                    usually 0 (a steady wind) */
    float period;                /* s, > 0; usually 2 */
    float jitter;                /* degrees, 0 to 90; usually 0 */
} cvk_gusts_desc;

/* Air on the cloths (the "wind" block of a scene file). Without it no aerodynamic work is
   recorded; with it, even at zero velocity, moving cloth feels the drag of still air. */
typedef struct cvk_wind_desc {
    bool enabled;                /* true: air acts on every cloth by its aero coefficients */
    float velocity[3];           /* m/s, the mean wind; usually [0, 0, 0] (still air) */
    cvk_gusts_desc gusts;
} cvk_wind_desc;

typedef struct cvk_scene_desc {
    const char* name;            /* for messages and output; may be NULL */
    float dt;                    /* substep length, s; > 0, usually 0.002 */
    uint32_t substeps;           /* substeps per frame (frame time = dt · substeps), usually 8 */
    uint32_t frames;             /* default frame count for the tools, usually 240 */
    bool integrate;              /* false: no inertia or gravity, only the solver moves particles */
    float gravity[3];            /* m/s², usually [0, −9.81, 0] */
    float damping;               /* fraction of velocity removed per substep, 0 ≤ damping < 1 */
    cvk_solver_desc solver;
    const cvk_cloth_desc* cloths;
    uint32_t cloth_count;        /* ≥ 1 */
    cvk_render_desc render;      /* read by the renderer only */
    cvk_collision_desc collision;
    const cvk_collider_desc* colliders;
    uint32_t collider_count;     /* 0: nothing to collide with (no collision work is recorded
                                    unless collision.self) */
    const cvk_attachment_desc* attachments; /* keyframed kinematic particles; zero-initialised
                                    fields are the defaults */
    uint32_t attachment_count;   /* 0: none (no attachment pass is recorded) */
    cvk_wind_desc wind;          /* air: wind, gusts and drag; usually off */
    float air_density;           /* kg/m³, > 0; usually 1.2 */
    uint32_t cookie_;            /* set by cvk_default_scene_desc; do not touch */
} cvk_scene_desc;

/* Defaults: see the field comments and README.md. */
CVK_API cvk_scene_desc cvk_default_scene_desc(void);
/* `solver` with its method's defaults filled in (tolerance, max_iterations; for pd the
   outer_iterations that max_iterations implies): what a simulation runs. */
CVK_API cvk_solver_desc cvk_solver_desc_resolve(const cvk_solver_desc* solver);
CVK_API cvk_cloth_desc cvk_default_cloth_desc(void);
CVK_API cvk_render_desc cvk_default_render_desc(void); /* the same as cvk_default_scene_desc().render */
CVK_API cvk_collider_desc cvk_default_collider_desc(void); /* a plane through the origin, +y up */

/* "plane", "sphere", "box", "capsule", "funnel", "mesh"; NULL for an unknown value. */
CVK_API const char* cvk_collider_type_name(cvk_collider_type type);

/* Checks every field; on failure the message starts with the key path ("cloths.0.mass: ..."). */
CVK_API cvk_result cvk_scene_desc_validate(const cvk_scene_desc* desc, cvk_error* error);

/* "rbgs", "jacobi", "chebyshev", "gs-cpu"; NULL for an unknown value. */
CVK_API const char* cvk_linear_solver_name(cvk_linear_solver linear);
CVK_API const char* cvk_method_name(cvk_method method);
/* "euler", "rk2", "adams-bashforth", "verlet" ("none" for NONE); NULL for an unknown value. */
CVK_API const char* cvk_integrator_name(cvk_integrator integrator);
/* "spring", "viscosity" ("none" for NONE); NULL for an unknown value. */
CVK_API const char* cvk_damping_model_name(cvk_damping_model model);

/* A scene loaded from JSON: owns its description and everything it points to. */
typedef struct cvk_scene cvk_scene;

/* Reads a JSON scene file. Each override is "key.path=value": the value is parsed as JSON
   (a bare word that is not JSON is taken as a string) and replaces or adds the key at that
   dotted path (array elements by index: "cloths.0.grid=[32,32]") before validation.
   Messages name the file and the key path:
   "scene.json: cloths.0.mass: must be greater than 0, got -1". */
CVK_API cvk_result cvk_scene_load(const char* path, const char* const* overrides, uint32_t override_count,
                          cvk_scene** out_scene, cvk_error* error);
/* The same from text in memory; source_name stands in for the file name in messages. A
   relative "mesh" path is kept as written, so it is relative to the working directory
   (cvk_scene_load joins it to the scene file's folder, in the scene's own memory). */
CVK_API cvk_result cvk_scene_parse(const char* json_text, const char* source_name,
                           const char* const* overrides, uint32_t override_count,
                           cvk_scene** out_scene, cvk_error* error);
CVK_API const cvk_scene_desc* cvk_scene_get_desc(const cvk_scene* scene);
CVK_API void cvk_scene_destroy(cvk_scene* scene);

/* ----------------------------------------------------------------------------------------
 * Simulation
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_sim cvk_sim;

/* Zero means default for every field but scene. */
typedef struct cvk_sim_desc {
    const cvk_scene_desc* scene; /* copied; need not outlive the call */
    uint32_t workgroup_size;     /* compute workgroup size for every pass, 0 = the library's
                                    choice: 64, and on CPU devices the device's subgroup size
                                    for the passes that stream over particles (the sweeps) */
    uint32_t max_workgroups;     /* workgroups per dispatch, 0 = the library's choice: a few on
                                    CPU devices, where each costs a thread hand-off, one per
                                    workgroup_size particles elsewhere */
    int timing;                  /* GPU timestamps per pass: 0 = on where supported, -1 = off */
    bool grab;                   /* true: the frame has the grab pass from the start, so frames
                                    you record now follow cvk_sim_grab; false: the first
                                    cvk_sim_grab adds it (see there) */
    uint32_t search_lanes;       /* invocations that share one particle's candidate search
                                    (self-contact), dividing workgroup_size; 0 = the
                                    library's choice: 1 on CPU devices, 16 elsewhere (fewer
                                    where 16 does not divide workgroup_size; 1 where the lanes'
                                    lists, 128 bytes per invocation, exceed the device's shared
                                    memory). The candidates do not depend on it */
} cvk_sim_desc;

CVK_API cvk_result cvk_sim_create(cvk_context* context, const cvk_sim_desc* desc, cvk_sim** out_sim,
                          cvk_error* error);
/* Waits until the context's queue is idle (work you recorded may still use the simulation's
   buffers), then frees everything the simulation made. */
CVK_API void cvk_sim_destroy(cvk_sim* sim);

/* Records `frames` frames (each dt · substeps of simulated time) into `cmd`, which must be
   in the recording state, outside a render pass, from a pool of the context's queue family.
   Nothing is submitted and nothing waits. Each submission of `cmd` advances the simulation
   by `frames` frames; `cmd` may be submitted again without re-recording.

   Synchronisation contract:
   - The library binds its own compute pipelines, descriptor sets and push constants: state
     you bound for compute before the call is lost.
   - It begins with a barrier that makes earlier compute-shader and transfer writes visible
     to its compute shaders, records barriers between its own passes, and ends after its last
     dispatch without a trailing barrier.
   - Before another stage reads the particle positions you record a barrier from
     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT / VK_ACCESS_SHADER_WRITE_BIT to that stage.
   - Once the simulation has the grab pass (cvk_sim_grab, cvk_sim_desc.grab), every frame
     reads a host-visible buffer that cvk_sim_grab and cvk_sim_release write from the host:
     call them only while no submission of these frames is executing (see cvk_sim_grab).
   - Fails with CVK_ERROR_UNSUPPORTED for the host solver "gs-cpu" (use cvk_sim_step). */
CVK_API cvk_result cvk_sim_record(cvk_sim* sim, VkCommandBuffer cmd, uint32_t frames, cvk_error* error);

/* Advances `frames` frames and waits until they are done: one submission of a command
   buffer recorded once at creation, one host wait at the end. CVK_ERROR_DIVERGED when the
   simulation blew up (now or before; the message names the frame and the cloth): its
   positions stopped advancing there, and stepping on changes nothing until a state is
   written (cvk_sim_write_state, cvk_sim_load_snapshot). */
CVK_API cvk_result cvk_sim_step(cvk_sim* sim, uint32_t frames, cvk_error* error);

/* Number of particles over all cloths. */
CVK_API uint64_t cvk_sim_particle_count(const cvk_sim* sim);

/* Copies positions out (3 floats per particle, cloth by cloth; a grid in row-major order, i
   fastest; a mesh in file order, see cvk_cloth_desc). Waits for the device to be idle on the context's queue; `count` is the number
   of particles the array holds and must be cvk_sim_particle_count(). */
CVK_API cvk_result cvk_sim_read_positions(cvk_sim* sim, float* xyz, uint64_t count, cvk_error* error);

/* Replaces all positions (same order) and sets every velocity to zero. Pinned particles
   are held at their new place. */
CVK_API cvk_result cvk_sim_write_positions(cvk_sim* sim, const float* xyz, uint64_t count,
                                   cvk_error* error);

/* The full state, for snapshots: positions (m) and velocities (m/s), 3 floats per particle in
   the order of cvk_sim_read_positions. The velocity is Verlet's at the end of the last
   substep, (x_n − x_{n−1}) / h + h g / 2 (0 for a cloth at rest; for a pinned particle 0, for an
   attached one the motion's (x_n − x_{n−1}) / h).
   Either array may be NULL; waits like cvk_sim_read_positions. */
CVK_API cvk_result cvk_sim_read_state(cvk_sim* sim, float* xyz, float* velocity, uint64_t count,
                              cvk_error* error);

/* Replaces positions and velocities (velocity NULL: at rest). Writing back what
   cvk_sim_read_state returned continues the same motion, to float rounding of the velocity.
   Pinned particles are held at their new place and keep no velocity. Non-finite values are
   rejected with CVK_ERROR_INVALID_ARGUMENT and change nothing. */
CVK_API cvk_result cvk_sim_write_state(cvk_sim* sim, const float* xyz, const float* velocity,
                               uint64_t count, cvk_error* error);

/* Exact snapshots, for resuming a run bit for bit (cvk_sim_read_state goes through float
   velocities and is not exact). A snapshot is an opaque byte string: a 64-byte header (magic
   "CVKSNAP", format version, particle count, frames simulated, a hash of the scene as built,
   the solver family and linear solver) and the solver's state as it holds it (for the device
   solvers positions and last displacements, vec4 floats; for gs-cpu its double arrays).
   cvk_sim_snapshot_size is its size in bytes under the current solver (0 for NULL).
   cvk_sim_save_snapshot waits like cvk_sim_read_positions; `size` must be that size.
   cvk_sim_load_snapshot puts the state and the frame counter back, so stepping on gives the
   bits the saved simulation would have given. It refuses, with CVK_ERROR_INVALID_ARGUMENT
   (CVK_ERROR_UNSUPPORTED for another format version) and changing nothing: data that is not a
   snapshot, one of another scene (particle count or build hash differ), a size other than
   the header says (truncated), and state the current solver cannot take exactly: a device
   solver's snapshot loads into any device solver (rbgs, jacobi, chebyshev), gs-cpu's only
   into gs-cpu. Byte order is the machine's. */
CVK_API uint64_t cvk_sim_snapshot_size(const cvk_sim* sim);
CVK_API cvk_result cvk_sim_save_snapshot(cvk_sim* sim, void* data, uint64_t size, cvk_error* error);
CVK_API cvk_result cvk_sim_load_snapshot(cvk_sim* sim, const void* data, uint64_t size,
                                         cvk_error* error);

/* The cloths as the simulation sees them: particle and triangle ranges, in scene order. */
typedef struct cvk_cloth_info {
    const char* name;            /* the scene's name for the cloth; "cloth<N>" when it has none */
    uint32_t first_particle;     /* range in the order of cvk_sim_read_positions */
    uint32_t particle_count;
    uint32_t first_triangle;     /* range in cvk_sim_read_mesh's triangles */
    uint32_t triangle_count;
    bool mesh;                   /* true: read from a mesh file; false: a grid */
} cvk_cloth_info;

CVK_API uint32_t cvk_sim_cloth_count(const cvk_sim* sim);
/* Zeroes for a cloth index out of range. */
CVK_API cvk_cloth_info cvk_sim_get_cloth(const cvk_sim* sim, uint32_t cloth);
/* Triangles over all cloths, torn ones included. */
CVK_API uint64_t cvk_sim_triangle_count(const cvk_sim* sim);

/* The cloths as triangles, for export through your own pipeline (clothvk-sim --obj uses it):
   positions (m) and unit vertex normals (the area-weighted average of the live triangles'
   normals, on the side the triangles wind counter-clockwise; zero at a vertex with none),
   3 floats per particle in the order of cvk_sim_read_positions, and 3 particle indices per
   triangle, cloth by cloth (cvk_cloth_info ranges). A triangle whose springs are gone (torn)
   has three equal indices: skip it. Any array may be NULL; vertex_count must be
   cvk_sim_particle_count() and triangle_count cvk_sim_triangle_count(). Waits like
   cvk_sim_read_positions. */
CVK_API cvk_result cvk_sim_read_mesh(cvk_sim* sim, float* xyz, float* normals, uint32_t* triangles,
                                     uint64_t vertex_count, uint64_t triangle_count,
                                     cvk_error* error);

/* Changes the solver (linear solver, iterations, omega, Chebyshev parameters) at run time,
   without rebuilding the scene; positions and velocities are kept, so the next step continues
   the same motion with the new solver. The description is checked as in a scene ("solver.omega:
   must be between 0 and 2, got 2.5"); a bad one, or a failure before the switch, leaves the
   old solver in place. Waits for the simulation's earlier work. Command buffers recorded with
   cvk_sim_record before the call still hold the old plan: record them again. */
CVK_API cvk_result cvk_sim_set_solver(cvk_sim* sim, const cvk_solver_desc* solver, cvk_error* error);

/* The solver settings in use. */
CVK_API cvk_solver_desc cvk_sim_get_solver(const cvk_sim* sim);

#define CVK_MAX_PASSES 12

/* GPU time of one kind of pass over the last completed frame. */
typedef struct cvk_pass_stats {
    const char* name;          /* "predict", "solve" */
    double gpu_ms;             /* summed over the frame's substeps; < 0 when not measured */
    uint32_t dispatches;       /* per frame */
} cvk_pass_stats;

typedef struct cvk_sim_stats {
    uint64_t particles;        /* all particles */
    uint64_t pinned;           /* of which pinned */
    uint64_t springs[3];       /* structural, shear, bend */
    uint64_t torn_springs;     /* springs broken by tearing so far (cvk_tearing_desc); the spring
                                  metrics below leave them out */
    uint32_t colours;          /* particle colours of the Gauss-Seidel sweep */
    uint64_t frames;           /* frames advanced with cvk_sim_step */
    double residual;           /* Σ (|xa − xb| − L)² over structural springs (seed 002 eq. 4.1), m² */
    double residual_per_type[3];/* the same sum for structural, shear and bend springs, m² */
    double residual_normalized;/* residual / (structural springs · mean L²); dimensionless */
    double max_stretch;        /* max over all springs of |xa − xb| / L − 1 */
    double p99_stretch;        /* 99th percentile (nearest rank) of |xa − xb| / L − 1 over the
                                  structural springs: the stretch of all but the worst 1 % */
    uint64_t nan_count;        /* coordinates that are NaN or infinite; 0 in a healthy run */
    double kinetic_energy;     /* Σ ½ m |v|² over free particles, J */
    double gravitational_energy;/* −Σ m g·x over free particles (0 at the origin; 0 without
                                  integration), J */
    double elastic_energy;     /* Σ ½ k (|xa − xb| − L)² over all springs, J */
    double energy;             /* the sum, J: for stability studies (pinned particles moved
                                  by a write add or remove energy from outside) */
    double gpu_ms_per_frame;   /* GPU time of the last completed frame; < 0 when not measured */
    uint32_t dispatches_per_frame;
    uint32_t dispatches_per_substep;
    uint32_t pass_count;
    cvk_pass_stats passes[CVK_MAX_PASSES];
    /* Contact, at the end of the last frame (0 in a scene without collision). */
    uint64_t collider_contacts;  /* free particles within the thickness of a collider's surface */
    uint64_t self_contacts;      /* particle–triangle pairs of the cloths within the thickness
                                    (pairs skipped as close in the rest mesh not counted) */
    double max_penetration;      /* m: deepest a particle is inside any collider's surface
                                    (0 when none is; thickness not counted) */
    uint64_t intersecting_pairs; /* non-adjacent cloth triangle pairs that intersect
                                    (cvk_sim_count_intersections); 0 without collision */
    uint64_t contact_searches;   /* searches for cloth-contact candidates so far (since creation
                                    or the last snapshot loaded; adaptive by default, see
                                    collision.detect_every); 0 without self-contact */
    /* The linear solver: implicit's, and pd's sweeps (counted on the device with a tolerance;
       without one, every sweep the plan records). */
    uint32_t solver_iterations;       /* CG iterations or Jacobi sweeps (pd: sweeps) of the last
                                         frame, summed over its substeps */
    uint64_t solver_iterations_total; /* since the simulation started */
    uint32_t solver_breakdowns;       /* substeps whose solve found the system not positive
                                         definite (pᵀAp ≤ 0, rᵀP⁻¹r < 0) and stopped; 0 with
                                         the clamp */
    float solver_residual;            /* pd with a tolerance: the last relative residual
                                         measured (solver.tolerance's measure); else 0 */
    /* The divergence watch (GPU solvers): a non-finite position, a particle faster than
       10000 m/s or a spring ten times its rest length stops the simulation at the last sane
       state. */
    bool diverged;               /* the simulation blew up; its state stopped advancing */
    uint64_t diverged_frame;     /* the frame (0-based, as stats.frames counts) it happened in */
    uint32_t diverged_cloth;     /* the cloth (scene order) of the first particle that did */
    bool diverged_nonfinite;     /* true: a position became NaN or infinite; false: ran away */
} cvk_sim_stats;

/* ----------------------------------------------------------------------------------------
 * Picking and dragging: the interaction an engine needs (seed 002 §5.3.8)
 * ------------------------------------------------------------------------------------- */

/* A particle: its cloth (scene order) and its index in that cloth, in the order of
   cvk_sim_read_positions from cvk_cloth_info.first_particle (a grid's [i, j] is
   j · grid[0] + i). */
typedef struct cvk_particle {
    uint32_t cloth;
    uint32_t index;
} cvk_particle;

typedef struct cvk_pick_result {
    bool hit;                    /* false: the ray passes no particle within the radius */
    cvk_particle particle;       /* the particle hit nearest the origin */
    float distance;              /* m along the ray from its origin to the point of the ray
                                    nearest the particle */
    float position[3];           /* the particle's position, m: where a drag starts */
} cvk_pick_result;

/* The particle nearest the ray's origin among those the ray passes within `radius` (m, ≥ 0;
   usually about half the particle spacing) of, in front of the origin (distance ≥ 0), computed
   on the device over every particle, pinned ones included. The direction need not be unit
   length. Equal distances go to the cloth, then the index, that comes first: the answer is
   the same every run. A miss is not an error: out->hit is false. A ray with a non-finite
   origin, a zero or non-finite direction or a negative or non-finite radius is refused with
   CVK_ERROR_INVALID_ARGUMENT. It is a query outside the frame: one submission of its own,
   waited for like cvk_sim_read_positions; recorded frames are not touched. */
CVK_API cvk_result cvk_sim_pick(cvk_sim* sim, const float origin[3], const float direction[3],
                                float radius, cvk_pick_result* out, cvk_error* error);

/* Drags a particle: from the next frame on, `particle` moves in a straight line from where each
   frame finds it to `target` (m), evenly over the frame's substeps, and is at the target at its
   end (to float rounding); the solver holds it there as infinitely heavy, so the cloth follows
   through its springs (tethers and contact do not move it). Calling it again moves the target
   or grabs another particle (one at a time: the one before is released). A pinned or attached
   particle is refused (CVK_ERROR_INVALID_ARGUMENT), as is a non-finite target. Only the pd
   method with a device linear solver (rbgs, jacobi, chebyshev) holds a grab: the others are
   refused with CVK_ERROR_UNSUPPORTED, and cvk_sim_set_solver refuses to switch to them while a
   particle is grabbed.

   cvk_sim_release lets the particle go: it is free again from the next frame on, with the
   velocity of its last substep (still if the target stood still, moving if it was dragged).

   A grab is not part of the state: snapshots and cvk_sim_write_state neither save nor clear
   it.

   Synchronisation: the target lives in a small host-visible buffer that every recorded frame
   reads; cvk_sim_grab and cvk_sim_release write it at once from the host and submit nothing.
   So call them only while no submitted frame of this simulation is executing: cvk_sim_step has
   waited already; if you record frames yourself (cvk_sim_record), wait on your fence first.
   The frames submitted after the call see the new target; a command buffer recorded earlier
   does too, and need not be recorded again, with one exception: the first cvk_sim_grab of a
   simulation made without cvk_sim_desc.grab adds the grab pass to the frame (waiting for the
   queue, as cvk_sim_set_solver does), and command buffers recorded before it must be recorded
   again. */
CVK_API cvk_result cvk_sim_grab(cvk_sim* sim, cvk_particle particle, const float target[3],
                                cvk_error* error);
/* As cvk_sim_grab, with a hand instead of a fingertip: every free particle of the same cloth
   within `radius` m of `particle`, where they are when the grab starts, is held too, each at its
   offset from `particle` (so the region moves rigidly with the target); at most 64, the
   nearest first (ties: the lower index). A load on one particle concentrates in its own
   springs, so with tearing a one-particle drag plucks that particle out; spread over a region
   it tears the cloth. The grab starts by reading the positions back (it waits, like
   cvk_sim_read_positions); calling it again with the same particle and radius only moves the
   target (no wait). Radius 0 grabs the one particle. A negative or non-finite radius is
   refused with CVK_ERROR_INVALID_ARGUMENT; the rest as cvk_sim_grab. */
CVK_API cvk_result cvk_sim_grab_within(cvk_sim* sim, cvk_particle particle, float radius,
                                       const float target[3], cvk_error* error);
CVK_API void cvk_sim_release(cvk_sim* sim);

/* The number of pairs of cloth triangles that share no particle and intersect, computed exactly
   on the host from the current positions (waits like cvk_sim_read_positions). Torn triangles
   are skipped. A cloth that does not pass through itself or another has 0. */
CVK_API cvk_result cvk_sim_count_intersections(cvk_sim* sim, uint64_t* out_pairs, cvk_error* error);

/* Reads positions back (as cvk_sim_read_positions) and computes the statistics. For frames
   you recorded yourself, call it once their submission has completed. */
CVK_API cvk_result cvk_sim_get_stats(cvk_sim* sim, cvk_sim_stats* out_stats, cvk_error* error);

/* Fills only the counting and timing fields of `out_stats` (GPU time of the last completed
   frame, per pass, dispatch counts) without reading anything back; cheap enough per frame. */
CVK_API void cvk_sim_get_timing(const cvk_sim* sim, cvk_sim_stats* out_stats);

/* Writes a human-readable description of the step plan (passes, dispatches, workgroups)
   into `text`, truncated to `capacity` bytes; returns the length it needed. */
CVK_API size_t cvk_sim_describe_plan(const cvk_sim* sim, char* text, size_t capacity);

/* ----------------------------------------------------------------------------------------
 * Mesh: triangles and vertex normals of the cloths, generated on the device
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_mesh cvk_mesh;

/* Zero means default for every field. */
typedef struct cvk_mesh_desc {
    VkBufferUsageFlags vertex_usage; /* usage added to the vertex buffer's (vertex, storage,
                                        transfer source), e.g. for your own compute pass */
    VkBufferUsageFlags index_usage;  /* usage added to the index buffer's (index, storage,
                                        transfer source) */
} cvk_mesh_desc;

/* Every cloth's triangles, in the vertex and index buffers the mesh owns. desc may be NULL.
   The mesh reads the simulation's particles and must be destroyed before it. Works on a
   compute-only queue (drawing is then up to you, on a queue that can). */
CVK_API cvk_result cvk_mesh_create(cvk_sim* sim, const cvk_mesh_desc* desc, cvk_mesh** out_mesh,
                                   cvk_error* error);
CVK_API void cvk_mesh_destroy(cvk_mesh* mesh);

/* The triangles of one cloth: a range of the index buffer, for one draw call. */
typedef struct cvk_mesh_range {
    uint32_t first_index;
    uint32_t index_count;        /* 3 per triangle: 6 (grid[0] − 1)(grid[1] − 1) for a grid */
} cvk_mesh_range;

/* What to bind to draw the mesh. The buffers live until cvk_mesh_destroy. */
typedef struct cvk_mesh_buffers {
    VkBuffer vertex_buffer;      /* one vertex per particle, in the order of
                                    cvk_sim_read_positions */
    uint32_t vertex_count;
    uint32_t vertex_stride;      /* bytes from one vertex to the next: 32 */
    uint32_t position_offset;    /* 0: position, 3 floats (VK_FORMAT_R32G32B32_SFLOAT), m; a 4th
                                    float, 1, follows */
    uint32_t normal_offset;      /* 16: unit normal, 3 floats, on the side the triangles wind
                                    counter-clockwise (a grid: u_axis × v_axis);
                                    zero at a vertex with no triangle; a 4th float, 0, follows */
    VkBuffer index_buffer;       /* triangle lists; a triangle whose constraints are gone (torn)
                                    has three equal indices, so it draws nothing */
    VkIndexType index_type;      /* VK_INDEX_TYPE_UINT32 */
    uint32_t index_count;        /* all cloths */
    uint32_t cloth_count;
    const cvk_mesh_range* cloths; /* one range per cloth, in scene order; owned by the mesh */
} cvk_mesh_buffers;

CVK_API cvk_mesh_buffers cvk_mesh_get_buffers(const cvk_mesh* mesh);

/* Records the mesh generation — one compute dispatch that writes every vertex (position and
   area-weighted normal) and every triangle from the current particles — into `cmd`, which is
   recording, outside a render pass, from a pool of the context's queue family. Nothing is
   submitted and nothing waits; record it after cvk_sim_record in the same command buffer (or
   a later submission) and before your draw.

   Synchronisation contract (the VkFFT model: the library records its own barriers, you record
   the one into your stage):
   - The library begins with one barrier from COMPUTE_SHADER (shader writes: the simulation's
     positions) and, on a queue with graphics, VERTEX_INPUT (your earlier draws from these
     buffers, a write-after-read hazard) to COMPUTE_SHADER (shader reads and writes).
   - Its compute shader writes the vertex and index buffers (VK_ACCESS_SHADER_WRITE_BIT). It
     binds its own compute pipeline, descriptor set and push constants: compute state you bound
     before is lost. It ends without a trailing barrier.
   - Before you draw, record a barrier from VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT /
     VK_ACCESS_SHADER_WRITE_BIT to VK_PIPELINE_STAGE_VERTEX_INPUT_BIT /
     VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT (or to whatever stage
     reads the buffers).
   - If a stage other than vertex input or a compute shader reads the buffers, make it finish
     before the next cvk_mesh_record (an execution barrier from that stage to
     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT). */
CVK_API cvk_result cvk_mesh_record(cvk_mesh* mesh, VkCommandBuffer cmd, cvk_error* error);

/* ----------------------------------------------------------------------------------------
 * Renderer: offscreen images of the mesh, shadow-mapped, no window system
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_renderer cvk_renderer;

/* Draws `mesh` as its render description says (usually &scene->render): a shadow pass from
   the key light into a depth map, then the lit pass — the cloth lit, shadowed and
   multisampled, then resolved in linear light over the ground and sky (one sample per pixel:
   they have no edges to smooth) into an sRGB image — copied into a host-visible buffer.
   Needs a queue family with graphics: on a compute-only queue it fails with
   CVK_ERROR_UNSUPPORTED. Fails with CVK_ERROR_DEVICE_LIMIT when the image, the shadow map or
   the sample count is more than the device allows. desc is copied; the mesh must outlive the
   renderer. Everything is created here, pipelines compiled and one frame drawn: no frame
   creates anything. */
CVK_API cvk_result cvk_renderer_create(cvk_mesh* mesh, const cvk_render_desc* desc,
                                       cvk_renderer** out_renderer, cvk_error* error);
CVK_API void cvk_renderer_destroy(cvk_renderer* renderer);

/* Records one frame into `cmd` (recording, outside a render pass, from a pool of the
   context's queue family): the mesh generation (cvk_mesh_record and its barrier), a barrier
   from the compute shader to vertex input, the shadow pass, the lit pass, a copy of the image
   into the renderer's host-visible buffer and a barrier from that copy to HOST reads (so do
   not record cvk_mesh_record for it yourself). Record it after cvk_sim_record to draw the
   frame just simulated. The renderer's images, buffers and
   timestamp queries are its own; the render passes order every access to them, frame after
   frame. One submission of a renderer's frame may be in flight at a time. Graphics and compute
   state you bound before the call is lost. In a scene with colliders (drawn where the
   simulation's own buffer says they are) it ends with an execution barrier from the vertex
   shader to compute shaders, so the next recorded simulation frame does not move them while
   they are drawn. */
CVK_API cvk_result cvk_renderer_record(cvk_renderer* renderer, VkCommandBuffer cmd, cvk_error* error);

/* Draws one frame of the current particles and waits: a command buffer recorded once, one
   submission, one host wait. */
CVK_API cvk_result cvk_renderer_draw(cvk_renderer* renderer, cvk_error* error);

/* Pixels in memory: RGBA, 8 bits per channel, sRGB-encoded, rows top to bottom. */
typedef struct cvk_image {
    const uint8_t* pixels;
    uint32_t width, height;
    uint32_t row_bytes;          /* bytes from one row to the next, at least 4 · width */
} cvk_image;

/* The last frame drawn, in the renderer's host-visible buffer: valid until the next
   submission of one of its frames (read it after cvk_renderer_draw returns, or after the
   submission you recorded with cvk_renderer_record has completed). Alpha is 255. */
CVK_API cvk_image cvk_renderer_get_image(const cvk_renderer* renderer);

/* Device time of the last completed frame, per pass; < 0 where not measured. */
typedef struct cvk_render_timing {
    double mesh_ms;              /* mesh generation */
    double shadow_ms;            /* shadow pass */
    double lit_ms;               /* lit pass: the multisampled cloth, then its resolve over the
                                    ground and sky */
    double readback_ms;          /* copy of the image into the host-visible buffer */
    double total_ms;
} cvk_render_timing;

CVK_API cvk_render_timing cvk_renderer_get_timing(const cvk_renderer* renderer);

/* Where the camera ended up once the automatic placement was done. */
typedef struct cvk_render_view {
    float eye[3], target[3], up[3];
    float fov_y;                 /* degrees */
    float view_proj[16];         /* world -> Vulkan clip space, column-major (x right, y down,
                                    depth 1 at the near plane and 0 at the far one) */
    float ground_height;         /* m along up */
    float reach_min[3], reach_max[3]; /* the box the camera frames: where the cloths can go */
} cvk_render_view;

CVK_API cvk_render_view cvk_renderer_get_view(const cvk_renderer* renderer);

/* Moves a camera with keyframes (render.camera_keyframes) to where it is at `seconds` of
   simulated time, for the frames drawn from now on (a renderer starts at time 0); without
   keyframes it does nothing. Call it while no frame of the renderer is in flight. */
CVK_API void cvk_renderer_set_time(cvk_renderer* renderer, double seconds);

/* Writes an image as a PNG file: to a temporary name in the same folder, then renamed, so the
   file is complete or absent; a path that exists and is not a regular file (a device, FIFO,
   folder or link) is refused with CVK_ERROR_IO rather than replaced. An opaque image (every
   alpha 255) is written as RGB.
   Compression is fast (zlib level 2), not smallest. */
CVK_API cvk_result cvk_image_write_png(const cvk_image* image, const char* path, cvk_error* error);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_H */
