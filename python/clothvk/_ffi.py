"""The C declarations clothvk's Python layer calls, and where libclothvk is found.

cffi's ABI mode: nothing is compiled when the package is installed, so the struct layouts
below must match lib/include/clothvk.h field for field (python/tests/test_layout.py compiles
a C program that prints every declared struct's size and field offsets and compares them).
Vulkan handles are pointers here; the Python layer never passes or reads them.
"""

import ctypes.util
import os
import pathlib

import cffi

CDEF = r"""
typedef void* VkInstance;
typedef void* VkPhysicalDevice;
typedef void* VkDevice;
typedef void* VkQueue;

typedef enum cvk_result {
    CVK_SUCCESS = 0,
    CVK_ERROR_INVALID_ARGUMENT = 1,
    CVK_ERROR_IO = 2,
    CVK_ERROR_PARSE = 3,
    CVK_ERROR_UNSUPPORTED = 4,
    CVK_ERROR_DEVICE_LIMIT = 5,
    CVK_ERROR_OUT_OF_MEMORY = 6,
    CVK_ERROR_VULKAN = 7,
    CVK_ERROR_DIVERGED = 8,
    CVK_ERROR_DEVICE_LOST = 9,
} cvk_result;

typedef struct cvk_error {
    cvk_result result;
    char message[512];
} cvk_error;

const char* cvk_result_name(cvk_result result);
const char* cvk_version(void);

typedef struct cvk_context cvk_context;
typedef void (*cvk_log_fn)(void* user, const char* message);

typedef struct cvk_context_desc {
    int validation;
    const char* device_name;
    cvk_log_fn log;
    void* log_user;
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
    uint32_t cookie_;
} cvk_context_desc;

cvk_context_desc cvk_default_context_desc(void);
cvk_result cvk_context_create(const cvk_context_desc* desc, cvk_context** out_context,
                              cvk_error* error);
void cvk_context_destroy(cvk_context* context);

typedef struct cvk_context_info {
    const char* device_name;
    uint32_t api_version;
    bool adopted;
    bool validation;
    bool timestamps;
    uint32_t subgroup_size;
    uint64_t max_particles;
    bool graphics;
    uint32_t max_image_size;
    uint64_t device_bytes;
    uint64_t device_peak_bytes;
} cvk_context_info;

cvk_context_info cvk_context_get_info(const cvk_context* context);
uint32_t cvk_context_validation_message_count(const cvk_context* context);

typedef enum cvk_method { CVK_METHOD_PD = 0, CVK_METHOD_IMPLICIT = 1, CVK_METHOD_EXPLICIT = 2 } cvk_method;
typedef enum cvk_integrator {
    CVK_INTEGRATOR_NONE = 0,
    CVK_INTEGRATOR_EULER = 1,
    CVK_INTEGRATOR_RK2 = 2,
    CVK_INTEGRATOR_AB4 = 3,
    CVK_INTEGRATOR_VERLET = 4,
} cvk_integrator;
typedef enum cvk_fuse { CVK_FUSE_AUTO = 0, CVK_FUSE_ON = 1, CVK_FUSE_OFF = 2 } cvk_fuse;
typedef enum cvk_damping_model {
    CVK_DAMPING_NONE = 0,
    CVK_DAMPING_SPRING = 1,
    CVK_DAMPING_VISCOSITY = 2,
} cvk_damping_model;
typedef enum cvk_linear_solver {
    CVK_LINEAR_RBGS = 0,
    CVK_LINEAR_JACOBI = 1,
    CVK_LINEAR_CHEBYSHEV = 2,
    CVK_LINEAR_GS_CPU = 3,
    CVK_LINEAR_CG = 4,
} cvk_linear_solver;

typedef struct cvk_solver_desc {
    cvk_method method;
    cvk_linear_solver linear;
    uint32_t outer_iterations;
    uint32_t inner_iterations;
    float omega;
    float chebyshev_rho;
    uint32_t chebyshev_delay;
    float tolerance;
    uint32_t max_iterations;
    float kd;
    cvk_integrator integrator;
    cvk_damping_model damping_model;
    uint32_t tether_every;
    float strain_limit;
    cvk_fuse fuse;
} cvk_solver_desc;

typedef struct cvk_stiffness {
    float structural;
    float shear;
    float bend;
} cvk_stiffness;

typedef struct cvk_transform {
    float scale[3];
    float rotation[4];
    float translation[3];
} cvk_transform;

typedef struct cvk_box3 {
    float min[3];
    float max[3];
} cvk_box3;

typedef struct cvk_aero_desc {
    float drag;
    float lift;
    float friction;
} cvk_aero_desc;

typedef struct cvk_tearing_desc {
    float max_stretch;
} cvk_tearing_desc;

typedef struct cvk_cloth_desc {
    const char* name;
    uint32_t grid[2];
    float size[2];
    float origin[3];
    float u_axis[3];
    float v_axis[3];
    const char* mesh;
    cvk_transform transform;
    float rest_scale;
    float mass;
    float density;
    cvk_stiffness stiffness;
    const uint32_t (*pins)[2];
    uint32_t pin_count;
    const uint32_t* pin_vertices;
    uint32_t pin_vertex_count;
    bool use_pin_box;
    cvk_box3 pin_box;
    float color[3];
    const char* texture;
    float texture_scale[2];
    float velocity[3];
    float tethers;
    cvk_aero_desc aero;
    cvk_tearing_desc tearing;
    float back_color[3];
    float sheen;
    float roughness;
    float thickness;
    const char* normal_map;
    float normal_strength;
    bool material_texture;
    uint32_t cookie_;
} cvk_cloth_desc;

typedef struct cvk_keyframe {
    float time;
    float translation[3];
    float rotation[4];
} cvk_keyframe;

typedef struct cvk_motion {
    const cvk_keyframe* keyframes;
    uint32_t keyframe_count;
    bool loop;
} cvk_motion;

typedef struct cvk_attachment_desc {
    uint32_t cloth;
    const uint32_t (*pins)[2];
    uint32_t pin_count;
    const uint32_t* pin_vertices;
    uint32_t pin_vertex_count;
    bool use_pin_box;
    cvk_box3 pin_box;
    cvk_motion motion;
    uint32_t cookie_;
} cvk_attachment_desc;

typedef struct cvk_collision_desc {
    bool self;
    float thickness;
    float radius;
    float friction;
    float static_friction;
    bool allow_intersecting_start;
    uint32_t detection_interval;
    uint32_t detect_every;
    float exclusion;
    bool edges;
} cvk_collision_desc;

typedef enum cvk_collider_type {
    CVK_COLLIDER_PLANE = 0,
    CVK_COLLIDER_SPHERE = 1,
    CVK_COLLIDER_BOX = 2,
    CVK_COLLIDER_CAPSULE = 3,
    CVK_COLLIDER_FUNNEL = 4,
    CVK_COLLIDER_MESH = 5,
    CVK_COLLIDER_TYPE_COUNT = 6,
} cvk_collider_type;

typedef struct cvk_collider_desc {
    cvk_collider_type type;
    const char* name;
    float point[3];
    float normal[3];
    float center[3];
    float radius;
    float half_extents[3];
    float rotation[4];
    float a[3], b[3];
    float apex[3];
    float funnel_a;
    float height;
    const char* file;
    cvk_transform transform;
    float friction;
    float static_friction;
    cvk_motion motion;
    float color[3];
    float roughness;
    const char* texture;
    float texture_scale;
    uint32_t cookie_;
} cvk_collider_desc;

typedef struct cvk_light {
    float direction[3];
    float color[3];
} cvk_light;

typedef struct cvk_camera_keyframe {
    float time;
    float eye[3];
    float target[3];
} cvk_camera_keyframe;

typedef struct cvk_render_desc {
    uint32_t size[2];
    bool auto_eye;
    float eye[3];
    bool auto_target;
    float target[3];
    float up[3];
    float fov_y;
    cvk_light key;
    cvk_light fill;
    float ambient[3];
    float background[3];
    bool ground;
    bool auto_ground_height;
    float ground_height;
    float ground_color[3];
    uint32_t shadow_map_size;
    uint32_t samples;
    bool wireframe;
    const cvk_camera_keyframe* camera_keyframes;
    uint32_t camera_keyframe_count;
    bool camera_loop;
    bool soft_shadows;
    float key_angle;
    bool sky_light;
    bool ao;
    float ao_radius;
    uint32_t smooth;
    bool tone_map;
    bool fit;
    float fit_margin;
    bool overlay;
    float vertex_lighting;
    uint32_t cookie_;
} cvk_render_desc;

typedef struct cvk_gusts_desc {
    float amplitude;
    float period;
    float jitter;
} cvk_gusts_desc;

typedef struct cvk_wind_desc {
    bool enabled;
    float velocity[3];
    cvk_gusts_desc gusts;
} cvk_wind_desc;

typedef struct cvk_instances_desc {
    uint32_t count;
    float spacing[3];
    const float (*offsets)[3];
} cvk_instances_desc;

typedef struct cvk_scene_desc {
    const char* name;
    float dt;
    uint32_t substeps;
    uint32_t frames;
    bool integrate;
    float gravity[3];
    float damping;
    cvk_solver_desc solver;
    const cvk_cloth_desc* cloths;
    uint32_t cloth_count;
    cvk_render_desc render;
    cvk_collision_desc collision;
    const cvk_collider_desc* colliders;
    uint32_t collider_count;
    const cvk_attachment_desc* attachments;
    uint32_t attachment_count;
    cvk_wind_desc wind;
    float air_density;
    cvk_instances_desc instances;
    uint32_t cookie_;
} cvk_scene_desc;

cvk_render_desc cvk_default_render_desc(void);
cvk_solver_desc cvk_solver_desc_resolve(const cvk_solver_desc* solver);
cvk_collider_desc cvk_default_collider_desc(void);
const char* cvk_collider_type_name(cvk_collider_type type);
const char* cvk_linear_solver_name(cvk_linear_solver linear);

typedef struct cvk_scene cvk_scene;
cvk_result cvk_scene_load(const char* path, const char* const* overrides, uint32_t override_count,
                          cvk_scene** out_scene, cvk_error* error);
cvk_result cvk_scene_parse(const char* json_text, const char* source_name,
                           const char* const* overrides, uint32_t override_count,
                           cvk_scene** out_scene, cvk_error* error);
const cvk_scene_desc* cvk_scene_get_desc(const cvk_scene* scene);
void cvk_scene_destroy(cvk_scene* scene);

typedef struct cvk_sim cvk_sim;
typedef struct cvk_sim_desc {
    const cvk_scene_desc* scene;
    uint32_t workgroup_size;
    uint32_t max_workgroups;
    int timing;
    bool grab;
    int fused_shared_memory;
    uint32_t search_lanes;
    uint32_t cookie_;
} cvk_sim_desc;

cvk_sim_desc cvk_default_sim_desc(void);
cvk_result cvk_sim_create(cvk_context* context, const cvk_sim_desc* desc, cvk_sim** out_sim,
                          cvk_error* error);
void cvk_sim_destroy(cvk_sim* sim);
cvk_result cvk_sim_step(cvk_sim* sim, uint32_t frames, cvk_error* error);
uint64_t cvk_sim_particle_count(const cvk_sim* sim);
cvk_result cvk_sim_read_positions(cvk_sim* sim, float* xyz, uint64_t count, cvk_error* error);
cvk_result cvk_sim_write_positions(cvk_sim* sim, const float* xyz, uint64_t count,
                                   cvk_error* error);
cvk_result cvk_sim_read_state(cvk_sim* sim, float* xyz, float* velocity, uint64_t count,
                              cvk_error* error);
cvk_result cvk_sim_write_state(cvk_sim* sim, const float* xyz, const float* velocity,
                               uint64_t count, cvk_error* error);

typedef struct cvk_cloth_info {
    const char* name;
    uint32_t first_particle;
    uint32_t particle_count;
    uint32_t first_triangle;
    uint32_t triangle_count;
    bool mesh;
} cvk_cloth_info;

uint32_t cvk_sim_cloth_count(const cvk_sim* sim);
cvk_cloth_info cvk_sim_get_cloth(const cvk_sim* sim, uint32_t cloth);
uint64_t cvk_sim_triangle_count(const cvk_sim* sim);
cvk_result cvk_sim_read_mesh(cvk_sim* sim, float* xyz, float* normals, uint32_t* triangles,
                             uint64_t vertex_count, uint64_t triangle_count, cvk_error* error);
cvk_result cvk_sim_set_solver(cvk_sim* sim, const cvk_solver_desc* solver, cvk_error* error);

typedef struct cvk_particle {
    uint32_t cloth;
    uint32_t index;
} cvk_particle;

typedef struct cvk_pick_result {
    bool hit;
    cvk_particle particle;
    float distance;
    float position[3];
} cvk_pick_result;

cvk_result cvk_sim_pick(cvk_sim* sim, const float origin[3], const float direction[3],
                        float radius, cvk_pick_result* out, cvk_error* error);
cvk_result cvk_sim_grab(cvk_sim* sim, cvk_particle particle, const float target[3],
                        cvk_error* error);
cvk_result cvk_sim_grab_within(cvk_sim* sim, cvk_particle particle, float radius,
                               const float target[3], cvk_error* error);
void cvk_sim_release(cvk_sim* sim);
cvk_solver_desc cvk_sim_get_solver(const cvk_sim* sim);

#define CVK_MAX_PASSES 24

typedef struct cvk_pass_stats {
    const char* name;
    double gpu_ms;
    uint32_t dispatches;
} cvk_pass_stats;

typedef struct cvk_sim_stats {
    uint64_t particles;
    uint64_t pinned;
    uint64_t springs[3];
    uint64_t torn_springs;
    uint32_t colours;
    uint64_t frames;
    double residual;
    double residual_per_type[3];
    double residual_normalized;
    double max_stretch;
    double p99_stretch;
    uint64_t nan_count;
    double kinetic_energy;
    double gravitational_energy;
    double elastic_energy;
    double energy;
    double gpu_ms_per_frame;
    uint32_t dispatches_per_frame;
    uint32_t dispatches_per_substep;
    uint32_t pass_count;
    cvk_pass_stats passes[24];
    uint64_t collider_contacts;
    uint64_t self_contacts;
    double max_penetration;
    uint64_t intersecting_pairs;
    uint64_t contact_searches;
    uint64_t contact_held;
    double contact_held_fraction;
    bool contact_cut;
    uint64_t contact_crowded;
    uint32_t solver_iterations;
    uint64_t solver_iterations_total;
    uint32_t solver_breakdowns;
    float solver_residual;
    bool diverged;
    uint64_t diverged_frame;
    uint32_t diverged_cloth;
    bool diverged_nonfinite;
} cvk_sim_stats;

cvk_result cvk_sim_count_intersections(cvk_sim* sim, uint64_t* out_pairs, cvk_error* error);
uint32_t cvk_sim_note_count(const cvk_sim* sim);
const char* cvk_sim_note(const cvk_sim* sim, uint32_t index);
cvk_result cvk_sim_get_stats(cvk_sim* sim, cvk_sim_stats* out_stats, cvk_error* error);
size_t cvk_sim_describe_plan(const cvk_sim* sim, char* text, size_t capacity);

typedef struct cvk_mesh cvk_mesh;
cvk_result cvk_mesh_create(cvk_sim* sim, const void* desc, cvk_mesh** out_mesh,
                           cvk_error* error);
void cvk_mesh_destroy(cvk_mesh* mesh);

typedef struct cvk_renderer cvk_renderer;
cvk_result cvk_renderer_create(cvk_mesh* mesh, const cvk_render_desc* desc,
                               cvk_renderer** out_renderer, cvk_error* error);
void cvk_renderer_destroy(cvk_renderer* renderer);
cvk_result cvk_renderer_draw(cvk_renderer* renderer, cvk_error* error);

typedef struct cvk_image {
    const uint8_t* pixels;
    uint32_t width, height;
    uint32_t row_bytes;
} cvk_image;

cvk_image cvk_renderer_get_image(const cvk_renderer* renderer);
cvk_result cvk_image_write_png(const cvk_image* image, const char* path, cvk_error* error);
"""

# Structs declared above, for the layout test: all of them.
STRUCTS = (
    "cvk_error", "cvk_context_desc", "cvk_context_info", "cvk_solver_desc", "cvk_stiffness",
    "cvk_transform", "cvk_box3", "cvk_aero_desc", "cvk_tearing_desc", "cvk_cloth_desc",
    "cvk_keyframe", "cvk_motion", "cvk_attachment_desc", "cvk_collision_desc",
    "cvk_collider_desc", "cvk_light", "cvk_camera_keyframe", "cvk_render_desc",
    "cvk_gusts_desc", "cvk_wind_desc", "cvk_instances_desc", "cvk_scene_desc", "cvk_sim_desc",
    "cvk_cloth_info",
    "cvk_pass_stats", "cvk_sim_stats", "cvk_image", "cvk_particle", "cvk_pick_result",
)

ffi = cffi.FFI()
ffi.cdef(CDEF)


def library_candidates():
    """Where libclothvk is looked for, in order: $CLOTHVK_LIBRARY, the package's own folder
    (where pip install puts it), the build tree of the repository this package sits in
    (build/lib), then the system's library path."""
    found = []
    explicit = os.environ.get("CLOTHVK_LIBRARY")
    if explicit:
        return [explicit]
    here = pathlib.Path(__file__).resolve().parent
    for candidate in (here / "libclothvk.so", here.parents[1] / "build" / "lib" / "libclothvk.so"):
        if candidate.exists():
            found.append(str(candidate))
    system = ctypes.util.find_library("clothvk")
    if system:
        found.append(system)
    return found


def open_library():
    candidates = library_candidates()
    if not candidates:
        raise OSError("libclothvk not found: build it (meson setup build && meson compile -C "
                      "build), install it, or set CLOTHVK_LIBRARY to its path")
    return ffi.dlopen(candidates[0])


lib = open_library()
