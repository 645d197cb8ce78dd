/* clothvk/scene.h — step 2: what to simulate, as plain structs or read from a JSON scene file.
 *
 * Reading order: the solver, then one cloth (cvk_cloth_desc), motion over time (keyframes and
 * attachments), collisions (cvk_collision_desc, cvk_collider_desc), how the scene is drawn
 * (cvk_render_desc), the air, and the scene itself (cvk_scene_desc), which holds them all;
 * then the defaults, validation and scene files (cvk_scene_load). A scene file parses into
 * exactly one cvk_scene_desc: every key of the format is a field here.
 */
#ifndef CLOTHVK_SCENE_H
#define CLOTHVK_SCENE_H

#include "base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------------------------------------------------------------------
 * The solver and the cloths
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

/* Whether rbgs runs the sweeps of an outer iteration fused into one dispatch of one workgroup,
   or of a workgroup a copy for instances without self-contact (docs/performance.md, "Fused
   sweeps"): the same bits as one dispatch per colour and sweep. */
typedef enum cvk_fuse {
    CVK_FUSE_AUTO = 0, /* not fused: slower on every device measured, lavapipe and an NVIDIA
                          H200 (docs/performance.md, "Fused sweeps") */
    CVK_FUSE_ON,       /* fused wherever the scene allows, on any device */
    CVK_FUSE_OFF,      /* one dispatch per colour and sweep */
} cvk_fuse;

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
    float strain_limit;         /* pd on the device (rbgs, jacobi, chebyshev): after every outer
                                   iteration a spring longer than (1 + strain_limit) times its
                                   rest length is shortened to it, within the contact bounds;
                                   0 = none (the default), e.g. 0.05 for 5 % */
    cvk_fuse fuse;              /* rbgs: fused sweeps (auto, on, off); usually CVK_FUSE_AUTO */
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
    /* How the renderer draws it beyond color and texture (a scene file's "material" block, which
       also takes color and texture): */
    float back_color[3];         /* linear RGB in [0, 1] of the back face (the side the
                                    triangles wind clockwise); each < 0 (the default, −1): the
                                    front's colour or texture */
    float sheen;                 /* in [0, 1]: the soft rim of light a fabric's fibres give at
                                    grazing angles (a "Charlie" sheen lobe); usually 0.4 */
    float roughness;             /* in [0.1, 1]: how wide that rim spreads; usually 0.5 */
    float thickness;             /* m, in [0, 0.05]: drawn as a slab this thick (the two faces
                                    half of it off the middle along the normal, joined along
                                    the border); 0 (the default): one surface */
    const char* normal_map;      /* image file of tangent-space normals (8-bit RGB = (n + 1) / 2,
                                    as texture: mapped by the same texture coordinates, the
                                    tangent along u and the bitangent along v); NULL = none */
    float normal_strength;       /* in [0, 2]: how far the map tilts the normal (its x and y
                                    scaled); usually 1 */
    bool material_texture;       /* set by the scene reader when the texture came from the
                                    material block, so messages name material.texture */
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
    uint32_t cookie_;            /* set by cvk_default_attachment_desc; do not touch */
} cvk_attachment_desc;

/* ----------------------------------------------------------------------------------------
 * Collisions
 * ------------------------------------------------------------------------------------- */

/* Contact between cloths (self- and cloth-cloth) and the defaults of every collider. */
typedef struct cvk_collision_desc {
    bool self;                   /* contact between and within cloths; usually false */
    float thickness;             /* m: the distance kept between a particle and any surface
                                    (collider or cloth), at most 1; 0 = half the shortest rest
                                    length of any structural spring (the default) */
    float radius;                /* m: the contact radius: pairs of cloth primitives nearer
                                    than this are tracked by contact, and each particle's
                                    displacement bound is measured within it; more than the
                                    thickness, at most 1; 0 = 1.3 thicknesses (the
                                    default) */
    float friction;              /* Coulomb kinetic coefficient, ≥ 0; usually 0.3 */
    float static_friction;       /* static coefficient, ≥ friction; usually 0.4 */
    bool allow_intersecting_start; /* false (the default) refuses a scene whose cloths
                                    intersect at the start, with self (cvk_sim_create names the
                                    first pair), or one with a free particle more than the
                                    thickness inside a collider at time 0, with or without
                                    self; true simulates it anyway */
    uint32_t detection_interval; /* with self: a detection that only a particle's move asks
                                    for waits for substep N, 2N, ... of the run (N this), the
                                    particles that would pass their bounds held at them until
                                    then; 0 or 1 (the default): detect at the substep that
                                    asks; at most 64 */
    /* Keys of an earlier contact, kept so that old scenes load; they have no effect, and a
       simulation lists each one a scene sets in its notes (cvk_sim_note). */
    uint32_t detect_every;       /* no effect; 0 */
    float exclusion;             /* no effect; 0 */
    bool edges;                  /* no effect (edge–edge contact is always on); false */
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
    /* How the renderer draws it (a scene file's "material" block, which also takes color): */
    float color[3];              /* linear RGB for renderers; usually [0.55, 0.55, 0.6] */
    float roughness;             /* in [0.1, 1]: how wide and faint the highlight is (0.1: a
                                    small bright one, as polished wood; 1: broad and dim, as
                                    cast iron); usually 0.5 */
    const char* texture;         /* image file drawn in place of color (as cvk_cloth_desc.texture),
                                    or NULL; projected from the three axes of the collider's own
                                    frame and blended by its normal (no texture coordinates) */
    float texture_scale;         /* m of the collider per repeat of the texture, > 0; usually 1 */
    uint32_t cookie_;            /* set by cvk_default_collider_desc; do not touch */
} cvk_collider_desc;

/* ----------------------------------------------------------------------------------------
 * How the scene is drawn: the "render" block of a scene file
 *
 * A scene file carries its camera and lights beside its cloths, and cvk_scene_desc is the one
 * parsed form of a scene file, so the render description is a field of it (render). The
 * simulation never reads it; cvk_renderer_create takes it (&scene->render), or any other
 * description from cvk_default_render_desc().
 * ------------------------------------------------------------------------------------- */

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
    bool soft_shadows;           /* shadows widen with the distance from what casts them, by
                                    key_angle; false: a fixed 3-texel filter. Usually true */
    float key_angle;             /* angular diameter of the key light, degrees, in [0, 20];
                                    usually 3 */
    bool sky_light;              /* light from the sky (above, render.ambient plus a share of
                                    the background) and from the lit ground (below) in place of
                                    the flat ambient; usually true */
    bool ao;                     /* ambient occlusion: darken creases, and where cloth meets
                                    cloth, colliders or the ground; usually true */
    float ao_radius;             /* m: how far apart surfaces still shade each other; 0 = 4 %
                                    of the diagonal of what the camera frames (the default) */
    uint32_t smooth;             /* curved triangles (PN triangles, by tessellation): each cloth
                                    triangle drawn as smooth² pieces of the cubic patch through
                                    its vertices and normals, 2 to 8; 0 or 1: flat triangles
                                    (the default) */
    bool tone_map;               /* roll off light brighter than 0.6 smoothly towards white
                                    instead of clipping it; usually true */
    bool fit;                    /* frame what is there instead of the reach: the cloths'
                                    particles and the corners of the finite colliders' boxes,
                                    from the direction eye − target (both given) or the default
                                    one; usually false. The renderer frames the particles when
                                    it is made; cvk_renderer_fit frames them again or a box */
    float fit_margin;            /* with fit: the share of the image's height and width kept
                                    free on each side, in [0, 0.45]; usually 0.06 */
    bool overlay;                /* draw "frame N  t = X.XXX s" in the image's lower left
                                    corner (cvk_renderer_draw; the time of
                                    cvk_renderer_set_time); usually false */
    float vertex_lighting;       /* pixels: the cloths are lit at their vertices, not at every
                                    pixel, when every cloth triangle's longest edge spans at most
                                    this many pixels where the camera comes nearest what it
                                    frames (and no cloth has a normal map, render.smooth is off);
                                    0: always at every pixel. Usually 12 */
    uint32_t cookie_;            /* set by cvk_default_render_desc; do not touch */
} cvk_render_desc;

/* ----------------------------------------------------------------------------------------
 * Air: the "wind" block of a scene file
 * ------------------------------------------------------------------------------------- */

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

/* ----------------------------------------------------------------------------------------
 * Instances: the "instances" block of a scene file
 * ------------------------------------------------------------------------------------- */

/* Copies of the whole scene side by side: its cloths, colliders and attachments repeated count
   times, copy k translated by offsets[k] (k · spacing without offsets), each copy's colliders
   and attachments acting on its own cloths only and, with collision.self, no contact between
   copies (copies may overlap), so that thousands of small cloths step in the same passes (the
   same dispatches per frame) as one. cvk_scene_load expands the block when it reads the file:
   the description then holds all the copies in order, copy k's cloths at k · n … k · n + n − 1
   for n = cloth_count / count (colliders and attachments alike), and this field records how
   they were made. A description built in code lists its cloths itself and leaves count at 0;
   a count > 1 whose cloths and colliders are laid out so (both divisible by count) keeps its
   copies apart the same way. */
typedef struct cvk_instances_desc {
    uint32_t count;              /* copies; 0 or 1 = the scene as written (the default) */
    float spacing[3];            /* m from copy k to copy k + 1 when offsets is NULL */
    const float (*offsets)[3];   /* m, copy k's translation, count of them; NULL: k · spacing */
} cvk_instances_desc;

/* ----------------------------------------------------------------------------------------
 * The scene: everything above in one description
 * ------------------------------------------------------------------------------------- */

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
    cvk_render_desc render;      /* the file's "render" block: camera and lights, for
                                    cvk_renderer_create; the simulation ignores it */
    cvk_collision_desc collision;
    const cvk_collider_desc* colliders;
    uint32_t collider_count;     /* 0: nothing to collide with (no collision work is recorded
                                    unless collision.self) */
    const cvk_attachment_desc* attachments; /* keyframed kinematic particles, each from
                                    cvk_default_attachment_desc() */
    uint32_t attachment_count;   /* 0: none (no attachment pass is recorded) */
    cvk_wind_desc wind;          /* air: wind, gusts and drag; usually off */
    float air_density;           /* kg/m³, > 0; usually 1.2 */
    cvk_instances_desc instances; /* how a file's "instances" block expanded; count 0: none */
    uint32_t cookie_;            /* set by cvk_default_scene_desc; do not touch */
} cvk_scene_desc;

/* ----------------------------------------------------------------------------------------
 * Defaults, validation and names
 * ------------------------------------------------------------------------------------- */

/* Defaults: see the field comments and README.md. */
CVK_API cvk_scene_desc cvk_default_scene_desc(void);
/* `solver` with its method's defaults filled in (tolerance, max_iterations; for pd the
   outer_iterations that max_iterations implies): what a simulation runs. */
CVK_API cvk_solver_desc cvk_solver_desc_resolve(const cvk_solver_desc* solver);
CVK_API cvk_cloth_desc cvk_default_cloth_desc(void);
CVK_API cvk_render_desc cvk_default_render_desc(void); /* the same as cvk_default_scene_desc().render */
CVK_API cvk_collider_desc cvk_default_collider_desc(void); /* a plane through the origin, +y up */
/* Cloth 0, no particles yet (set pins, pin_vertices or pin_box), no keyframes. */
CVK_API cvk_attachment_desc cvk_default_attachment_desc(void);

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
/* "auto", "on", "off"; NULL for a value out of range. */
CVK_API const char* cvk_fuse_name(cvk_fuse fuse);

/* ----------------------------------------------------------------------------------------
 * Scene files
 * ------------------------------------------------------------------------------------- */

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
/* The scene as read, in one canonical line: the file's JSON with the overrides applied, keys
   sorted, no spaces, every number as a real in 17 digits (so "cloths.0.grid=[12,12]" and
   "[12, 12.0]" give the same text). Defaults are not filled in. Owned by the scene; NULL for NULL. */
CVK_API const char* cvk_scene_get_json(const cvk_scene* scene);
CVK_API void cvk_scene_destroy(cvk_scene* scene);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_SCENE_H */
