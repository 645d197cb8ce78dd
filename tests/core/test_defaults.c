/* Every description a create call reads comes from its cvk_default_*_desc() function: the
   values it returns (what a zeroed description meant before descriptions carried a cookie),
   and the refusal, with its sentence, of a description that skipped it; a refused create call
   leaves its output pointer NULL, a missing argument included. The scene, cloth and
   collider descriptions are checked in test_scene.c and test_scene_collide.c. */
#include "harness.h"

/* `r` is CVK_ERROR_INVALID_ARGUMENT with exactly `want` as the message. */
static void expect_refused(const char* call, cvk_result r, const cvk_error* err, const char* want)
{
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT, "%s returned %s, not CVK_ERROR_INVALID_ARGUMENT", call,
          cvk_result_name(r));
    CHECK(err->result == r, "%s: the error says %s, the call returned %s", call,
          cvk_result_name(err->result), cvk_result_name(r));
    CHECK(strcmp(err->message, want) == 0, "%s: message \"%s\", want \"%s\"", call, err->message,
          want);
}

/* ---- the context --------------------------------------------------------------------------- */

static void context_defaults(void)
{
    cvk_context_desc d = cvk_default_context_desc();
    CHECK(d.validation == 0, "validation %d, want 0 ($CLOTHVK_VALIDATION decides)", d.validation);
    CHECK(d.device_name == NULL, "device_name \"%s\", want NULL", d.device_name);
    CHECK(d.log == NULL && d.log_user == NULL, "a log callback by default");
    CHECK(d.instance == VK_NULL_HANDLE && d.physical_device == VK_NULL_HANDLE &&
              d.device == VK_NULL_HANDLE && d.queue == VK_NULL_HANDLE && d.queue_family == 0,
          "adoption handles set by default");
    CHECK(d.cookie_ != 0, "no cookie");
}

static void context_refuses_a_description_without_defaults(void)
{
    cvk_error err = {0};
    cvk_context* ctx = (cvk_context*)&err; /* anything but NULL: the call must clear it */
    cvk_context_desc zero = {0};
    cvk_result r = cvk_context_create(&zero, &ctx, &err);
    expect_refused("cvk_context_create", r, &err,
                   "cvk_context_create: the description did not come from "
                   "cvk_default_context_desc()");
    CHECK(ctx == NULL, "a context came back from a refused description");
    ctx = (cvk_context*)&err;
    r = cvk_context_create(NULL, &ctx, &err);
    expect_refused("cvk_context_create(NULL)", r, &err,
                   "cvk_context_create needs a description and an output pointer");
    CHECK(ctx == NULL, "cvk_context_create(NULL) left its output pointer set");
}

/* ---- the simulation ------------------------------------------------------------------------ */

/* A small scene: one free 12 × 9 cloth. */
typedef struct small_scene {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
} small_scene;

static void small_scene_init(small_scene* s)
{
    s->cloth = harness_falling_cloth();
    s->scene = cvk_default_scene_desc();
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
}

static void sim_defaults(void)
{
    cvk_sim_desc d = cvk_default_sim_desc();
    CHECK(d.scene == NULL, "a scene by default");
    CHECK(d.workgroup_size == 0, "workgroup_size %u, want 0 (the library's choice)",
          d.workgroup_size);
    CHECK(d.max_workgroups == 0, "max_workgroups %u, want 0 (the library's choice)",
          d.max_workgroups);
    CHECK(d.timing == 0, "timing %d, want 0 (on where supported)", d.timing);
    CHECK(!d.grab, "grab on by default");
    CHECK(d.search_lanes == 0, "search_lanes %u, want 0 (the library's choice)", d.search_lanes);
    CHECK(d.cookie_ != 0, "no cookie");
}

static void sim_refuses_a_description_without_defaults(cvk_context* ctx)
{
    small_scene s;
    small_scene_init(&s);
    cvk_error err = {0};
    cvk_sim* sim = (cvk_sim*)&err; /* anything but NULL: the call must clear it */
    cvk_sim_desc literal = {.scene = &s.scene};
    cvk_result r = cvk_sim_create(ctx, &literal, &sim, &err);
    expect_refused("cvk_sim_create", r, &err,
                   "cvk_sim_create: the description did not come from cvk_default_sim_desc()");
    CHECK(sim == NULL, "a simulation came back from a refused description");

    static const char needs[] = "cvk_sim_create needs a context, a description with a scene, "
                                "and an output pointer";
    sim = (cvk_sim*)&err;
    r = cvk_sim_create(NULL, &literal, &sim, &err);
    expect_refused("cvk_sim_create without a context", r, &err, needs);
    CHECK(sim == NULL, "cvk_sim_create without a context left its output pointer set");
    r = cvk_sim_create(ctx, NULL, &sim, &err);
    expect_refused("cvk_sim_create(NULL)", r, &err, needs);
    cvk_sim_desc no_scene = cvk_default_sim_desc();
    r = cvk_sim_create(ctx, &no_scene, &sim, &err);
    expect_refused("cvk_sim_create without a scene", r, &err, needs);

    cvk_sim_desc d = cvk_default_sim_desc();
    d.scene = &s.scene;
    REQUIRE_OK(cvk_sim_create(ctx, &d, &sim, &err), err);
    cvk_sim_destroy(sim);
}

/* ---- the mesh ------------------------------------------------------------------------------ */

static void mesh_defaults(void)
{
    cvk_mesh_desc d = cvk_default_mesh_desc();
    CHECK(d.vertex_usage == 0, "vertex_usage 0x%x, want 0 (nothing added)", d.vertex_usage);
    CHECK(d.index_usage == 0, "index_usage 0x%x, want 0 (nothing added)", d.index_usage);
    CHECK(d.cookie_ != 0, "no cookie");
}

static void mesh_refuses_a_description_without_defaults(cvk_context* ctx)
{
    small_scene s;
    small_scene_init(&s);
    cvk_error err = {0};
    cvk_sim* sim;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    cvk_mesh* mesh = (cvk_mesh*)&err; /* anything but NULL: the call must clear it */
    cvk_mesh_desc literal = {.vertex_usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT};
    cvk_result r = cvk_mesh_create(sim, &literal, &mesh, &err);
    expect_refused("cvk_mesh_create", r, &err,
                   "cvk_mesh_create: the description did not come from cvk_default_mesh_desc()");
    CHECK(mesh == NULL, "a mesh came back from a refused description");
    mesh = (cvk_mesh*)&err;
    r = cvk_mesh_create(NULL, NULL, &mesh, &err);
    expect_refused("cvk_mesh_create(NULL)", r, &err,
                   "cvk_mesh_create needs a simulation and an output pointer");
    CHECK(mesh == NULL, "cvk_mesh_create(NULL) left its output pointer set");

    /* NULL is the defaults, as before; so is the defaults function's description. */
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    cvk_mesh_destroy(mesh);
    cvk_mesh_desc d = cvk_default_mesh_desc();
    d.vertex_usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    REQUIRE_OK(cvk_mesh_create(sim, &d, &mesh, &err), err);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

/* ---- the renderer -------------------------------------------------------------------------- */

/* The values are checked in test_scene.c (check_default_render); here what the cookie adds. */
static void render_defaults(void)
{
    cvk_render_desc d = cvk_default_render_desc();
    CHECK(!d.wireframe && d.camera_keyframes == NULL && d.camera_keyframe_count == 0 &&
              !d.camera_loop,
          "a wireframe or a moving camera by default");
    CHECK(d.cookie_ != 0, "no cookie");
    CHECK(cvk_default_scene_desc().render.cookie_ == d.cookie_,
          "the scene's render description does not carry the defaults' cookie");
    cvk_error err;
    cvk_scene* file;
    REQUIRE_OK(cvk_scene_parse("{\"cloths\": [{}], \"render\": {\"size\": [64, 48]}}",
                               "defaults.json", NULL, 0, &file, &err),
               err);
    CHECK(cvk_scene_get_desc(file)->render.cookie_ == d.cookie_,
          "a scene file's render description does not carry the defaults' cookie");
    cvk_scene_destroy(file);
}

static void renderer_refuses_a_description_without_defaults(cvk_context* ctx)
{
    small_scene s;
    small_scene_init(&s);
    cvk_error err = {0};
    cvk_sim* sim;
    cvk_mesh* mesh;
    REQUIRE_OK(harness_sim_create(ctx, &s.scene, &sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    cvk_renderer* renderer = (cvk_renderer*)&err; /* anything but NULL: the call must clear it */
    cvk_render_desc literal = {.size = {64, 48}, .up = {0, 1, 0}, .fov_y = 35.0f, .samples = 1,
                               .shadow_map_size = 256};
    cvk_result r = cvk_renderer_create(mesh, &literal, &renderer, &err);
    expect_refused("cvk_renderer_create", r, &err,
                   "cvk_renderer_create: the description did not come from "
                   "cvk_default_render_desc()");
    CHECK(renderer == NULL, "a renderer came back from a refused description");
    renderer = (cvk_renderer*)&err;
    r = cvk_renderer_create(NULL, &literal, &renderer, &err);
    expect_refused("cvk_renderer_create(NULL)", r, &err,
                   "cvk_renderer_create needs a mesh, a render description and an output pointer");
    CHECK(renderer == NULL, "cvk_renderer_create(NULL) left its output pointer set");
    r = cvk_renderer_create(mesh, NULL, &renderer, &err);
    expect_refused("cvk_renderer_create(NULL)", r, &err,
                   "cvk_renderer_create needs a mesh, a render description and an output pointer");
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

int main(void)
{
    context_defaults();
    context_refuses_a_description_without_defaults();
    sim_defaults();
    mesh_defaults();
    render_defaults();
    cvk_context* ctx = harness_context();
    sim_refuses_a_description_without_defaults(ctx);
    mesh_refuses_a_description_without_defaults(ctx);
    renderer_refuses_a_description_without_defaults(ctx);
    return harness_finish(ctx);
}
