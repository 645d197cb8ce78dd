/* Scene descriptions and JSON scene files: defaults, every validation and loader message
   (compared exactly), overrides, NaN handling and the shipped scene files. The keys of a mesh
   cloth (mesh, transform, density, vertex pins, pin_box) are checked in test_scene_mesh.c. */
#include "scene_checks.h"

#include <math.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- defaults and names ---- */

static void check_default_scene(const cvk_scene_desc* d)
{
    CHECK_FLOAT(d->dt, 0.002f);
    CHECK_INT(d->substeps, 8);
    CHECK_INT(d->frames, 240);
    CHECK(d->integrate);
    CHECK_FLOAT(d->gravity[0], 0.0f);
    CHECK_FLOAT(d->gravity[1], -9.81f);
    CHECK_FLOAT(d->gravity[2], 0.0f);
    CHECK_FLOAT(d->damping, 0.0f);
    CHECK_INT(d->solver.method, CVK_METHOD_PD);
    CHECK_INT(d->solver.linear, CVK_LINEAR_RBGS);
    CHECK_INT(d->solver.outer_iterations, 4);
    CHECK_INT(d->solver.inner_iterations, 4);
    CHECK_FLOAT(d->solver.omega, 1.0f);
    CHECK_FLOAT(d->solver.chebyshev_rho, 0.0f);
    CHECK_INT(d->solver.chebyshev_delay, 2);
    CHECK_INT(d->solver.tether_every, 1);
}

static void check_default_cloth(const cvk_cloth_desc* c)
{
    CHECK_STR(c->name, NULL);
    CHECK_INT(c->grid[0], 100);
    CHECK_INT(c->grid[1], 100);
    CHECK_FLOAT(c->size[0], 1.0f);
    CHECK_FLOAT(c->size[1], 1.0f);
    CHECK_FLOAT(c->origin[0], -0.5f);
    CHECK_FLOAT(c->origin[1], 1.0f);
    CHECK_FLOAT(c->origin[2], 0.0f);
    CHECK_FLOAT(c->u_axis[0], 1.0f);
    CHECK_FLOAT(c->u_axis[1], 0.0f);
    CHECK_FLOAT(c->u_axis[2], 0.0f);
    CHECK_FLOAT(c->v_axis[0], 0.0f);
    CHECK_FLOAT(c->v_axis[1], 0.0f);
    CHECK_FLOAT(c->v_axis[2], 1.0f);
    CHECK_FLOAT(c->rest_scale, 1.0f);
    CHECK_FLOAT(c->mass, 0.1f);
    CHECK_FLOAT(c->stiffness.structural, 1e6f);
    CHECK_FLOAT(c->stiffness.shear, 0.0f);
    CHECK_FLOAT(c->stiffness.bend, 0.0f);
    CHECK(c->pins == NULL);
    CHECK_INT(c->pin_count, 0);
    CHECK_STR(c->mesh, NULL);
    for (int k = 0; k < 3; k++) {
        CHECK_FLOAT(c->transform.scale[k], 1.0f);
        CHECK_FLOAT(c->transform.translation[k], 0.0f);
        CHECK_FLOAT(c->pin_box.min[k], 0.0f);
        CHECK_FLOAT(c->pin_box.max[k], 0.0f);
    }
    CHECK_FLOAT(c->transform.rotation[0], 1.0f);
    CHECK_FLOAT(c->transform.rotation[1], 0.0f);
    CHECK_FLOAT(c->transform.rotation[2], 0.0f);
    CHECK_FLOAT(c->transform.rotation[3], 0.0f);
    CHECK_FLOAT(c->density, 0.0f);
    CHECK(c->pin_vertices == NULL);
    CHECK_INT(c->pin_vertex_count, 0);
    CHECK(!c->use_pin_box);
    CHECK_FLOAT(c->color[0], 0.9f);
    CHECK_FLOAT(c->color[1], 0.35f);
    CHECK_FLOAT(c->color[2], 0.3f);
}

static void check_default_render(const cvk_render_desc* r)
{
    CHECK_INT(r->size[0], 1280);
    CHECK_INT(r->size[1], 720);
    CHECK(r->auto_eye);
    CHECK(r->auto_target);
    CHECK_FLOAT(r->up[1], 1.0f);
    CHECK_FLOAT(r->fov_y, 35.0f);
    CHECK(r->ground);
    CHECK(r->auto_ground_height);
    CHECK_INT(r->shadow_map_size, 2048);
    CHECK_INT(r->samples, 4);
    CHECK(r->key.direction[1] > 0.0f);
    CHECK(r->key.color[0] > r->fill.color[0]);
}

static void test_defaults(void)
{
    cvk_scene_desc scene = cvk_default_scene_desc();
    CHECK_STR(scene.name, NULL);
    CHECK(scene.cloths == NULL);
    CHECK_INT(scene.cloth_count, 0);
    check_default_scene(&scene);
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    check_default_cloth(&cloth);
    check_default_render(&scene.render);
    cvk_render_desc render = cvk_default_render_desc();
    check_default_render(&render);
    fixture f;
    fixture_init(&f);
    EXPECT_DESC_VALID(&f.scene);
}

static void test_names(void)
{
    CHECK_STR(cvk_method_name(CVK_METHOD_PD), "pd");
    CHECK_STR(cvk_method_name(CVK_METHOD_IMPLICIT), "implicit");
    CHECK_STR(cvk_method_name(CVK_METHOD_EXPLICIT), "explicit");
    CHECK_STR(cvk_method_name((cvk_method)3), NULL);
    CHECK_STR(cvk_integrator_name(CVK_INTEGRATOR_AB4), "adams-bashforth");
    CHECK_STR(cvk_integrator_name((cvk_integrator)5), NULL);
    CHECK_STR(cvk_damping_model_name(CVK_DAMPING_VISCOSITY), "viscosity");
    CHECK_STR(cvk_damping_model_name((cvk_damping_model)3), NULL);
    CHECK_STR(cvk_linear_solver_name(CVK_LINEAR_RBGS), "rbgs");
    CHECK_STR(cvk_linear_solver_name(CVK_LINEAR_JACOBI), "jacobi");
    CHECK_STR(cvk_linear_solver_name(CVK_LINEAR_CHEBYSHEV), "chebyshev");
    CHECK_STR(cvk_linear_solver_name(CVK_LINEAR_GS_CPU), "gs-cpu");
    CHECK_STR(cvk_linear_solver_name(CVK_LINEAR_CG), "cg");
    CHECK_STR(cvk_linear_solver_name((cvk_linear_solver)5), NULL);
}

/* ---- validation of programmatic descriptions ---- */

static void test_validate_scene(void)
{
    fixture f;
    cvk_scene_desc zero = {0};
    EXPECT_DESC_INVALID(&zero, "scene description was not made by cvk_default_scene_desc()");
    EXPECT_DESC_INVALID(NULL, "scene description is NULL");
    CHECK_INT(cvk_scene_desc_validate(&zero, NULL), CVK_ERROR_INVALID_ARGUMENT);

    fixture_init(&f);
    f.scene.dt = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "dt: must be greater than 0, got 0");
    f.scene.dt = -0.001f;
    EXPECT_DESC_INVALID(&f.scene, "dt: must be greater than 0, got -0.001");
    f.scene.dt = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "dt: must be a finite number, got inf");
    f.scene.dt = NAN;
    EXPECT_DESC_INVALID(&f.scene, "dt: must be a finite number, got nan");
    /* The bound is 1e-6 as a float (a little less than 1e-6), as the docs promise 1e-6. */
    f.scene.dt = 1e-6f;
    EXPECT_DESC_VALID(&f.scene);
    f.scene.dt = 9.9e-7f;
    EXPECT_DESC_INVALID(&f.scene, "dt: must be at least 1e-06 s (1/dt² must fit single precision "
                        "with room for masses and stiffnesses), got 9.9e-07");

    fixture_init(&f);
    f.scene.substeps = 0;
    EXPECT_DESC_INVALID(&f.scene, "substeps: must be at least 1, got 0");
    fixture_init(&f);
    f.scene.frames = 0;
    EXPECT_DESC_INVALID(&f.scene, "frames: must be at least 1, got 0");

    fixture_init(&f);
    f.scene.gravity[1] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "gravity.1: must be a finite number, got nan");
    f.scene.gravity[1] = -NAN; /* printf would say "-nan" */
    EXPECT_DESC_INVALID(&f.scene, "gravity.1: must be a finite number, got nan");
    f.scene.gravity[1] = 1000.0f; /* any finite gravity */
    EXPECT_DESC_VALID(&f.scene);

    fixture_init(&f);
    f.scene.damping = 1.0f;
    EXPECT_DESC_INVALID(&f.scene, "damping: must be at least 0 and less than 1, got 1");
    f.scene.damping = -0.5f;
    EXPECT_DESC_INVALID(&f.scene, "damping: must be at least 0 and less than 1, got -0.5");
    f.scene.damping = 0.5f;
    EXPECT_DESC_VALID(&f.scene);
}

static void test_validate_solver(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.solver.method = (cvk_method)3;
    EXPECT_DESC_INVALID(&f.scene, "solver.method: unknown method 3");
    fixture_init(&f);
    f.scene.solver.linear = (cvk_linear_solver)9;
    EXPECT_DESC_INVALID(&f.scene, "solver.linear: unknown linear solver 9");
    fixture_init(&f);
    f.scene.solver.outer_iterations = 0;
    EXPECT_DESC_INVALID(&f.scene, "solver.outer_iterations: must be at least 1, got 0");
    fixture_init(&f);
    f.scene.solver.inner_iterations = 0;
    EXPECT_DESC_INVALID(&f.scene, "solver.inner_iterations: must be at least 1, got 0");
    fixture_init(&f);
    f.scene.solver.omega = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "solver.omega: must be greater than 0 and less than 2, got 0");
    f.scene.solver.omega = 2.0f;
    EXPECT_DESC_INVALID(&f.scene, "solver.omega: must be greater than 0 and less than 2, got 2");
    f.scene.solver.omega = 1.9f;
    EXPECT_DESC_VALID(&f.scene);
    f.scene.solver.chebyshev_rho = 1.0f;
    EXPECT_DESC_INVALID(&f.scene, "solver.chebyshev_rho: must be at least 0 and less than 1, got 1");
    f.scene.solver.chebyshev_rho = -0.5f;
    EXPECT_DESC_INVALID(&f.scene, "solver.chebyshev_rho: must be at least 0 and less than 1, got -0.5");
    f.scene.solver.chebyshev_rho = NAN;
    EXPECT_DESC_INVALID(&f.scene, "solver.chebyshev_rho: must be a finite number, got nan");
}

static void test_validate_cloth_list(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.cloths = NULL;
    EXPECT_DESC_INVALID(&f.scene, "cloths: a scene needs at least one cloth");
    fixture_init(&f);
    f.scene.cloth_count = 0;
    EXPECT_DESC_INVALID(&f.scene, "cloths: a scene needs at least one cloth");

    fixture_init(&f);
    f.scene.cloth_count = 2;
    f.cloths[1] = (cvk_cloth_desc){0};
    EXPECT_DESC_INVALID(&f.scene, "cloths.1: cloth description was not made by cvk_default_cloth_desc()");
    f.cloths[1] = cvk_default_cloth_desc();
    f.cloths[1].mass = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.1.mass: must be greater than 0, got 0");
}

static void test_validate_grid(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].grid[0] = 0;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.grid: each dimension must be at least 1, got [0, 100]");

    /* 2^30 particles is the most; one more fails, and the total runs over all cloths. */
    fixture_init(&f);
    f.cloths[0].grid[0] = 32768;
    f.cloths[0].grid[1] = 32768;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].grid[1] = 32769;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.0.grid: 1073774592 particles in all is more than clothvk supports (1073741824)");
    fixture_init(&f);
    f.scene.cloth_count = 3;
    for (int i = 0; i < 2; i++) {
        f.cloths[i].grid[0] = 32768;
        f.cloths[i].grid[1] = 16384;
    }
    f.cloths[2].grid[0] = 1;
    f.cloths[2].grid[1] = 1;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.2.grid: 1073741825 particles in all is more than clothvk supports (1073741824)");
    fixture_init(&f);
    f.cloths[0].grid[0] = UINT32_MAX;
    f.cloths[0].grid[1] = UINT32_MAX;
    EXPECT_DESC_INVALID(
        &f.scene, "cloths.0.grid: 18446744065119617025 particles in all is more than clothvk supports (1073741824)");
}

static void test_validate_geometry(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].size[0] = 0.0f;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.0.size.0: must be greater than 0 (the grid has 100 particles along it), got 0");
    /* A rope: one particle across, so no width is needed. */
    f.cloths[0].grid[0] = 1;
    f.cloths[0].grid[1] = 50;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].size[0] = -1.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.size.0: must be at least 0, got -1");
    f.cloths[0].size[0] = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.size.0: must be a finite number, got inf");

    fixture_init(&f);
    f.cloths[0].origin[2] = -INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.origin.2: must be a finite number, got -inf");

    fixture_init(&f);
    memset(f.cloths[0].u_axis, 0, sizeof f.cloths[0].u_axis);
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.u_axis: must not be zero, got [0, 0, 0]");
    fixture_init(&f);
    memset(f.cloths[0].v_axis, 0, sizeof f.cloths[0].v_axis);
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.v_axis: must not be zero, got [0, 0, 0]");
    fixture_init(&f);
    f.cloths[0].v_axis[0] = -2.0f;
    f.cloths[0].v_axis[2] = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.v_axis: must not be parallel to u_axis, got [-2, 0, 0]");
    f.cloths[0].v_axis[1] = 0.5f; /* not orthogonal, but spans a plane */
    EXPECT_DESC_VALID(&f.scene);
    fixture_init(&f);
    f.cloths[0].u_axis[1] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.u_axis.1: must be a finite number, got nan");
}

static void test_validate_material(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].rest_scale = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.rest_scale: must be greater than 0, got 0");
    fixture_init(&f);
    f.cloths[0].mass = -0.1f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.mass: must be greater than 0, got -0.1");
    fixture_init(&f);
    f.cloths[0].stiffness.shear = -1.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.stiffness.shear: must be at least 0, got -1");
    fixture_init(&f);
    f.cloths[0].stiffness.structural = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.stiffness.structural: must be a finite number, got nan");
    fixture_init(&f);
    f.cloths[0].stiffness.bend = -1e-3f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.stiffness.bend: must be at least 0, got -0.001");

    fixture_init(&f);
    f.cloths[0].color[1] = 1.5f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.color.1: must be between 0 and 1, got 1.5");
    f.cloths[0].color[1] = -0.25f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.color.1: must be between 0 and 1, got -0.25");
    f.cloths[0].color[1] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.color.1: must be a finite number, got nan");

    fixture_init(&f);
    f.cloths[0].texture = "";
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.texture: must name an image file, got an empty string");
    fixture_init(&f);
    f.cloths[0].texture_scale[1] = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.texture_scale.1: must be greater than 0, got 0");
    f.cloths[0].texture_scale[1] = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.texture_scale.1: must be a finite number, got inf");
}

static void test_validate_pins(void)
{
    static const uint32_t inside[][2] = {{0, 0}, {99, 99}};
    static const uint32_t outside[][2] = {{0, 0}, {100, 0}};
    fixture f;
    fixture_init(&f);
    f.cloths[0].pins = inside;
    f.cloths[0].pin_count = 2;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].pins = outside;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pins.1: [100, 0] is outside the 100 x 100 grid");
    f.cloths[0].pins = NULL;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pins: is NULL but pin_count is 2");
}

/* ---- JSON ---- */

static void test_validate_render(void)
{
    fixture f;
    fixture_init(&f);
    f.scene.render.size[0] = 0;
    EXPECT_DESC_INVALID(&f.scene, "render.size: each dimension must be at least 1, got [0, 720]");
    fixture_init(&f);
    f.scene.render.shadow_map_size = 8;
    EXPECT_DESC_INVALID(&f.scene, "render.shadow_map_size: must be from 16 to 16384, got 8");
    fixture_init(&f);
    f.scene.render.samples = 3;
    EXPECT_DESC_INVALID(&f.scene, "render.samples: must be 1, 2, 4 or 8, got 3");
    fixture_init(&f);
    f.scene.render.fov_y = 180.0f;
    EXPECT_DESC_INVALID(&f.scene, "render.fov_y: must be greater than 0 and less than 180, got 180");
    fixture_init(&f);
    f.scene.render.up[0] = f.scene.render.up[1] = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "render.up: must not be zero, got [0, 0, 0]");
    fixture_init(&f);
    f.scene.render.eye[1] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "render.eye.1: must be a finite number, got nan");
    fixture_init(&f);
    f.scene.render.key.direction[0] = f.scene.render.key.direction[1] = f.scene.render.key.direction[2] = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "render.key.direction: must not be zero, got [0, 0, 0]");
    fixture_init(&f);
    f.scene.render.fill.color[2] = -1.0f;
    EXPECT_DESC_INVALID(&f.scene, "render.fill.color.2: must be between 0 and 100, got -1");
    fixture_init(&f);
    f.scene.render.background[0] = 1.5f;
    EXPECT_DESC_INVALID(&f.scene, "render.background.0: must be between 0 and 1, got 1.5");
    fixture_init(&f);
    f.scene.render.ground_height = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "render.ground_height: must be a finite number, got inf");

    /* An explicit camera must see something: eye and target apart, up not along the view. */
    fixture_init(&f);
    f.scene.render.auto_eye = f.scene.render.auto_target = false;
    f.scene.render.eye[1] = f.scene.render.target[1] = 1.0f;
    EXPECT_DESC_INVALID(&f.scene, "render.target: must differ from render.eye, got [0, 1, 0] for both");
    f.scene.render.eye[1] = 3.0f;
    EXPECT_DESC_INVALID(&f.scene, "render.up: must not be parallel to the view direction (target - eye), got [0, 1, 0]");
    f.scene.render.eye[2] = 3.0f;
    EXPECT_DESC_VALID(&f.scene);
}

/* The render effects' keys and a cloth's material block: read into their fields; defaults. */
static void test_render_looks_json(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{'material': {'color': [0.1, 0.2, 0.3], 'back_color': [0.4, 0.5, "
                                "0.6], 'sheen': 0.7, 'roughness': 0.8, 'thickness': 0.05, 'normal_map': "
                                "'n.png', 'normal_strength': 1.5}}, {}], 'render': {'soft_shadows': false, "
                                "'key_angle': 5, 'sky_light': false, 'ao': false, 'ao_radius': 0.2, "
                                "'tone_map': false, 'vertex_lighting': 2.5}}");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        const cvk_cloth_desc* c = &d->cloths[0];
        CHECK_FLOAT(c->color[2], 0.3f);
        CHECK_FLOAT(c->back_color[0], 0.4f);
        CHECK_FLOAT(c->sheen, 0.7f);
        CHECK_FLOAT(c->roughness, 0.8f);
        CHECK_FLOAT(c->thickness, 0.05f);
        CHECK(c->normal_map && strstr(c->normal_map, "n.png"));
        CHECK_FLOAT(c->normal_strength, 1.5f);
        CHECK(!c->material_texture);
        CHECK_FLOAT(d->cloths[1].back_color[0], -1.0f);
        CHECK_FLOAT(d->cloths[1].sheen, 0.4f);
        CHECK_FLOAT(d->cloths[1].roughness, 0.5f);
        CHECK_FLOAT(d->cloths[1].thickness, 0.0f);
        CHECK(!d->cloths[1].normal_map);
        CHECK_FLOAT(d->cloths[1].normal_strength, 1.0f);
        const cvk_render_desc* r = &d->render;
        CHECK(!r->soft_shadows && !r->sky_light && !r->ao && !r->tone_map);
        CHECK_FLOAT(r->key_angle, 5.0f);
        CHECK_FLOAT(r->ao_radius, 0.2f);
        CHECK_FLOAT(r->vertex_lighting, 2.5f);
    }
    cvk_scene_destroy(scene);
    EXPECT_INVALID("{'cloths': [{'material': {'sheen': -0.1}}]}",
                   "t.json: cloths.0.material.sheen: must be between 0 and 1, got -0.1");
    EXPECT_INVALID("{'cloths': [{'material': {'thickness': 0.06}}]}",
                   "t.json: cloths.0.material.thickness: must be between 0 and 0.05, got 0.06");
    EXPECT_INVALID("{'cloths': [{'material': {'thickness': -0.001}}]}",
                   "t.json: cloths.0.material.thickness: must be between 0 and 0.05, got -0.001");
    EXPECT_INVALID("{'cloths': [{'material': {'normal_strength': 2.5}}]}",
                   "t.json: cloths.0.material.normal_strength: must be between 0 and 2, got 2.5");
    EXPECT_INVALID("{'cloths': [{'material': {'normal_map': ''}}]}",
                   "t.json: cloths.0.material.normal_map: must name an image file, got an empty string");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'key_angle': 30}}",
                   "t.json: render.key_angle: must be between 0 and 20, got 30");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'ao_radius': -1}}",
                   "t.json: render.ao_radius: must be between 0 and 100000, got -1");
}

/* render.wireframe and render.camera_keyframes: read, and each bad keyframe named. */
static void test_render_extras_json(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{}], 'render': {'wireframe': true, 'camera_loop': true,"
                                " 'camera_keyframes': [{'time': 0, 'eye': [1, 2, 3], 'target': [0, 1, 0]},"
                                " {'time': 2, 'eye': [-1, 2, 3], 'target': [0, 0.5, 0]}]}}");
    if (scene) {
        const cvk_render_desc* r = &cvk_scene_get_desc(scene)->render;
        CHECK(r->wireframe);
        CHECK(r->camera_loop);
        CHECK_INT(r->camera_keyframe_count, 2);
        CHECK_FLOAT(r->camera_keyframes[1].time, 2.0f);
        CHECK_FLOAT(r->camera_keyframes[1].eye[0], -1.0f);
        CHECK_FLOAT(r->camera_keyframes[1].target[1], 0.5f);
    }
    cvk_scene_destroy(scene);
    EXPECT_INVALID("{'cloths': [{}], 'render': {'camera_keyframes': [{'time': 0, 'eye': [1, 2, 3]}]}}",
                   "t.json: render.camera_keyframes.0.target: missing; a camera keyframe needs its target");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'camera_keyframes': [{'time': 1, 'eye': [1, 2, 3], 'target': [0, 0, 0]},"
                   " {'time': 1, 'eye': [1, 2, 3], 'target': [0, 0, 0]}]}}",
                   "t.json: render.camera_keyframes.1.time: must be greater than the previous keyframe's time (1), got 1");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'camera_keyframes': [{'time': 0, 'eye': [1, 2, 3], 'target': [1, 2, 3]}]}}",
                   "t.json: render.camera_keyframes.0.target: must differ from the keyframe's eye, got [1, 2, 3] for both");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'camera_keyframes': [{'time': 0, 'eye': [0, 2, 0], 'target': [0, 1, 0]}]}}",
                   "t.json: render.camera_keyframes.0.target: must not lie straight above or below the keyframe's eye "
                   "(along render.up)");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'camera_loop': true, 'camera_keyframes': [{'time': 0, 'eye': [1, 2, 3],"
                   " 'target': [0, 0, 0]}]}}",
                   "t.json: render.camera_loop: a looping camera needs at least two keyframes, got 1");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'camera_keyframes': {'time': 0}}}",
                   "t.json: render.camera_keyframes: expected an array of camera keyframe objects, got an object");
}

static void test_render_json(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{}], 'render': {'size': [320, 200], 'eye': [1, 2, 3], 'fov_y': 50,"
                                " 'key': {'direction': [0, 1, 0], 'color': [2, 2, 2]}, 'fill': {'color': [0, 0, 0]},"
                                " 'ambient': [0.1, 0.1, 0.1], 'background': [0, 0, 0], 'ground': false,"
                                " 'ground_height': -1, 'ground_color': [1, 1, 1], 'shadow_map_size': 512,"
                                " 'samples': 1, 'up': [0, 0, 1]}}");
    if (scene) {
        const cvk_render_desc* r = &cvk_scene_get_desc(scene)->render;
        CHECK_INT(r->size[0], 320);
        CHECK_INT(r->size[1], 200);
        CHECK(!r->auto_eye);
        CHECK(r->auto_target);
        CHECK_FLOAT(r->eye[2], 3.0f);
        CHECK_FLOAT(r->fov_y, 50.0f);
        CHECK_FLOAT(r->key.color[1], 2.0f);
        CHECK_FLOAT(r->fill.color[0], 0.0f);
        CHECK_FLOAT(r->fill.direction[0], cvk_default_render_desc().fill.direction[0]);
        CHECK(!r->ground);
        CHECK(!r->auto_ground_height);
        CHECK_FLOAT(r->ground_height, -1.0f);
        CHECK_INT(r->shadow_map_size, 512);
        CHECK_INT(r->samples, 1);
        CHECK_FLOAT(r->up[2], 1.0f);
    }
    cvk_scene_destroy(scene);

    const char* const size[] = {"render.size=[64, 48]", "render.target=[0, 1, 0]"};
    scene = PARSE_OK_SET("{'cloths': [{}]}", size);
    if (scene) {
        const cvk_render_desc* r = &cvk_scene_get_desc(scene)->render;
        CHECK_INT(r->size[0], 64);
        CHECK(r->auto_eye);
        CHECK(!r->auto_target);
        CHECK_FLOAT(r->target[1], 1.0f);
    }
    cvk_scene_destroy(scene);

    EXPECT_INVALID("{'cloths': [{}], 'render': {'fov': 40}}",
                   "t.json: render.fov: unknown key (expected one of: size, eye, target, up, fov_y, key, fill, "
                   "ambient, background, ground, ground_height, ground_color, shadow_map_size, samples, wireframe, "
                   "camera_keyframes, camera_loop, soft_shadows, key_angle, sky_light, ao, ao_radius, tone_map, smooth, "
                   "fit, overlay, vertex_lighting)");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'vertex_lighting': 65}}",
                   "t.json: render.vertex_lighting: must be between 0 and 64, got 65");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'key': {'colour': [1, 1, 1]}}}",
                   "t.json: render.key.colour: unknown key (expected one of: direction, color)");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'size': [0, 10]}}",
                   "t.json: render.size: each dimension must be at least 1, got [0, 10]");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'size': [-640, 480]}}",
                   "t.json: render.size.0: must be at least 1, got -640");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'ground': 'yes'}}",
                   "t.json: render.ground: expected true or false, got the string \"yes\"");
    EXPECT_INVALID("{'cloths': [{}], 'render': {'eye': [0, 1, 0], 'target': [0, 1, 0]}}",
                   "t.json: render.target: must differ from render.eye, got [0, 1, 0] for both");
    EXPECT_SET_ERROR("{'cloths': [{}]}", "render.samples=16", "t.json: render.samples (from --set): must be 1, 2, 4 or 8, got 16");
}

static void test_minimal_json(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{}]}");
    if (!scene)
        return;
    const cvk_scene_desc* d = cvk_scene_get_desc(scene);
    CHECK_STR(d->name, "t");
    check_default_scene(d);
    CHECK_INT(d->cloth_count, 1);
    check_default_cloth(&d->cloths[0]);
    cvk_scene_destroy(scene);

    /* The default name is the source name without directory and extension. */
    cvk_error err = {0};
    CHECK_INT(cvk_scene_parse("{\"cloths\": [{}]}", "dir/sub/my.scene.json", NULL, 0, &scene, &err), CVK_SUCCESS);
    CHECK_STR(cvk_scene_get_desc(scene)->name, "my.scene");
    cvk_scene_destroy(scene);
    CHECK_INT(cvk_scene_parse("{\"cloths\": [{}]}", NULL, NULL, 0, &scene, &err), CVK_SUCCESS);
    CHECK_STR(cvk_scene_get_desc(scene)->name, NULL);
    cvk_scene_destroy(scene);
    CHECK_INT(cvk_scene_parse("[]", NULL, NULL, 0, &scene, &err), CVK_ERROR_INVALID_ARGUMENT);
    CHECK_STR(err.message, "<string>: the top level must be an object, got an array of 0");

    CHECK(cvk_scene_get_desc(NULL) == NULL);
    cvk_scene_destroy(NULL);
}

static void test_full_json(void)
{
    cvk_scene* scene = PARSE_OK("{'name': 'full', 'dt': 0.001, 'substeps': 16, 'frames': 8.0, 'integrate': false,"
                                " 'gravity': [1, 2, 3], 'damping': 0.01,"
                                " 'solver': {'method': 'pd', 'linear': 'chebyshev', 'outer_iterations': 3,"
                                "   'inner_iterations': 5, 'omega': 0.9, 'chebyshev_rho': 0.95, 'chebyshev_delay': 0},"
                                " 'cloths': [{'name': 'a', 'grid': [3, 4], 'size': [2, 3], 'origin': [1, 2, 3],"
                                "   'u_axis': [0, 1, 0], 'v_axis': [0, 0, -1], 'rest_scale': 0.5, 'mass': 2,"
                                "   'stiffness': {'structural': 10, 'shear': 20, 'bend': 30},"
                                "   'pins': [[0, 0], [2, 3]], 'color': [0, 0.5, 1], 'texture_scale': [2, 3]},"
                                "  {'name': 'b'}]}");
    if (!scene)
        return;
    const cvk_scene_desc* d = cvk_scene_get_desc(scene);
    CHECK_STR(d->name, "full");
    CHECK_FLOAT(d->dt, 0.001f);
    CHECK_INT(d->substeps, 16);
    CHECK_INT(d->frames, 8);
    CHECK(!d->integrate);
    CHECK_FLOAT(d->gravity[0], 1.0f);
    CHECK_FLOAT(d->gravity[2], 3.0f);
    CHECK_FLOAT(d->damping, 0.01f);
    CHECK_INT(d->solver.method, CVK_METHOD_PD);
    CHECK_INT(d->solver.linear, CVK_LINEAR_CHEBYSHEV);
    CHECK_INT(d->solver.outer_iterations, 3);
    CHECK_INT(d->solver.inner_iterations, 5);
    CHECK_FLOAT(d->solver.omega, 0.9f);
    CHECK_FLOAT(d->solver.chebyshev_rho, 0.95f);
    CHECK_INT(d->solver.chebyshev_delay, 0);
    CHECK_INT(d->cloth_count, 2);
    const cvk_cloth_desc* c = &d->cloths[0];
    CHECK_STR(c->name, "a");
    CHECK_INT(c->grid[0], 3);
    CHECK_INT(c->grid[1], 4);
    CHECK_FLOAT(c->size[1], 3.0f);
    CHECK_FLOAT(c->origin[2], 3.0f);
    CHECK_FLOAT(c->u_axis[1], 1.0f);
    CHECK_FLOAT(c->v_axis[2], -1.0f);
    CHECK_FLOAT(c->rest_scale, 0.5f);
    CHECK_FLOAT(c->mass, 2.0f);
    CHECK_FLOAT(c->stiffness.structural, 10.0f);
    CHECK_FLOAT(c->stiffness.shear, 20.0f);
    CHECK_FLOAT(c->stiffness.bend, 30.0f);
    CHECK_INT(c->pin_count, 2);
    CHECK_INT(c->pins[1][0], 2);
    CHECK_INT(c->pins[1][1], 3);
    CHECK_FLOAT(c->color[1], 0.5f);
    CHECK_FLOAT(c->texture_scale[0], 2.0f);
    CHECK_FLOAT(c->texture_scale[1], 3.0f);
    CHECK_STR(d->cloths[1].name, "b");
    CHECK(d->cloths[1].texture == NULL);
    CHECK_FLOAT(d->cloths[1].texture_scale[1], 1.0f);
    CHECK_INT(d->cloths[1].grid[0], 100);
    cvk_scene_destroy(scene);

    scene = PARSE_OK("{'cloths': [{'grid': [1, 50], 'size': [0, 1]}]}");
    if (scene)
        CHECK_INT(cvk_scene_get_desc(scene)->cloths[0].grid[1], 50);
    cvk_scene_destroy(scene);
}

static void test_malformed_json(void)
{
    EXPECT_ERROR("{\n'dt': 1,\n'b' 2}", CVK_ERROR_PARSE, "t.json:3:5: malformed JSON: ':' expected near '2'");
    EXPECT_ERROR("{'dt': 1, 'dt': 2, 'cloths': [{}]}", CVK_ERROR_PARSE,
                 "t.json:1:14: malformed JSON: duplicate object key near '\"dt\"'");
    EXPECT_ERROR("{'cloths': [{'mass': 1, 'mass': 2}]}", CVK_ERROR_PARSE,
                 "t.json:1:30: malformed JSON: duplicate object key near '\"mass\"'");
    EXPECT_ERROR("", CVK_ERROR_PARSE, "t.json:1:0: malformed JSON: unexpected token near end of file");
    EXPECT_ERROR("{'dt': 1e400}", CVK_ERROR_PARSE, "t.json:1:12: malformed JSON: real number overflow near '1e400'");
    EXPECT_ERROR("{'cloths': [{}]} x", CVK_ERROR_PARSE, "t.json:1:18: malformed JSON: end of file expected near 'x'");
    // The text jansson quotes may hold a newline (a backslash at a line's end): the message
    // stays one line, the newline written as \x0a (found by tests/fuzz/fuzz_scene.c).
    EXPECT_ERROR("{'dt': 'a\\\nb'}", CVK_ERROR_PARSE,
                 "t.json:2:0: malformed JSON: invalid escape near '\"a\\\\x0a'");
}

static void test_nonfinite_json(void)
{
    EXPECT_INVALID("{'dt': NaN, 'cloths': [{}]}", "t.json: dt: must be a finite number, got NaN");
    EXPECT_INVALID("{'dt': nan, 'cloths': [{}]}", "t.json: dt: must be a finite number, got nan");
    EXPECT_INVALID("{'dt': Infinity, 'cloths': [{}]}", "t.json: dt: must be a finite number, got Infinity");
    EXPECT_INVALID("{'dt':-Infinity, 'cloths': [{}]}", "t.json: dt: must be a finite number, got -Infinity");
    EXPECT_INVALID("{'gravity': [0, -INF, 0], 'cloths': [{}]}", "t.json: gravity.1: must be a finite number, got -INF");
    EXPECT_INVALID("{'cloths': [{'mass': inf}]}", "t.json: cloths.0.mass: must be a finite number, got inf");
    EXPECT_INVALID("{'substeps': NaN, 'cloths': [{}]}", "t.json: substeps: expected a whole number, got NaN");
    EXPECT_INVALID("{'gravity': NaN, 'cloths': [{}]}", "t.json: gravity: expected an array of 3 numbers, got NaN");
    /* Beyond float range: refused as written, not as the infinity it would become. */
    EXPECT_INVALID("{'dt': 1e39, 'cloths': [{}]}", "t.json: dt: is too large for single precision "
                   "(at most 3.4028235e+38 in magnitude), got 1e+39");
    EXPECT_INVALID("{'gravity': [0, -1e39, 0], 'cloths': [{}]}", "t.json: gravity.1: is too large "
                   "for single precision (at most 3.4028235e+38 in magnitude), got -1e+39");
    /* Other bare words stay syntax errors. */
    EXPECT_ERROR("{'dt': NaNx, 'cloths': [{}]}", CVK_ERROR_PARSE, "t.json:1:11: malformed JSON: invalid token near 'NaNx'");
    EXPECT_ERROR("{'dt': Inf1}", CVK_ERROR_PARSE, "t.json:1:10: malformed JSON: invalid token near 'Inf'");
    /* Columns after a rewritten word count the user's text, not the added quotes. */
    EXPECT_ERROR("{'dt': NaN, 'x' 1}", CVK_ERROR_PARSE, "t.json:1:17: malformed JSON: ':' expected near '1'");
    EXPECT_ERROR("{'dt': NaN, 'g': NaN, 'x' 1}", CVK_ERROR_PARSE, "t.json:1:27: malformed JSON: ':' expected near '1'");
    EXPECT_ERROR("{'dt': NaN,\n 'x' 1}", CVK_ERROR_PARSE, "t.json:2:6: malformed JSON: ':' expected near '1'");
    /* Inside a string a word is just text. */
    cvk_scene* scene = PARSE_OK("{'name': 'NaN', 'cloths': [{}]}");
    if (scene)
        CHECK_STR(cvk_scene_get_desc(scene)->name, "NaN");
    cvk_scene_destroy(scene);
}

/* Numbers as written: one that would not read as itself in single precision is refused as
   written; integers of any length are numbers, past their bound with their value; values are
   printed with the digits that tell them apart. */
static void test_numbers_json(void)
{
    EXPECT_INVALID("{'cloths': [{'mass': 1e-50}]}", "t.json: cloths.0.mass: is too near 0 for single "
                   "precision, which reads it as 0 (the least magnitude is 1.4013e-45), got 1e-50");
    EXPECT_INVALID("{'colliders': [{'type': 'sphere', 'keyframes': [{'time': 0}, {'time': 1e-300}]}], "
                   "'cloths': [{}]}", "t.json: colliders.0.keyframes.1.time: is too near 0 for single "
                   "precision, which reads it as 0 (the least magnitude is 1.4013e-45), got 1e-300");
    EXPECT_INVALID("{'frames': 99999999999999999999, 'cloths': [{}]}",
                   "t.json: frames: must be at most 4294967295, got 1e+20");
    EXPECT_INVALID("{'frames': 4294967296, 'cloths': [{}]}",
                   "t.json: frames: must be at most 4294967295, got 4294967296");
    EXPECT_INVALID("{'substeps': -99999999999999999999, 'cloths': [{}]}",
                   "t.json: substeps: must be at least 1, got -1e+20");
    EXPECT_SET_ERROR("{'cloths': [{}]}", "frames=99999999999999999999",
                     "t.json: frames (from --set): must be at most 4294967295, got 1e+20");
    EXPECT_SET_ERROR("{'cloths': [{}]}", "frames=1e30",
                     "t.json: frames (from --set): must be at most 4294967295, got 1e+30");
    EXPECT_SET_ERROR("{'cloths': [{}]}", "dt=1e400",
                     "t.json: --set dt: 1e400 holds a number too large to read (beyond double precision)");
    EXPECT_INVALID("{'damping': 1.0000002, 'cloths': [{}]}",
                   "t.json: damping: must be at least 0 and less than 1, got 1.0000002");
    EXPECT_INVALID("{'colliders': [{'type': 'sphere', 'keyframes': [{'time': 1.0000002}, "
                   "{'time': 1.0000001}]}], 'cloths': [{}]}",
                   "t.json: colliders.0.keyframes.1.time: must be greater than the previous "
                   "keyframe's time (1.0000002), got 1.0000001");
    EXPECT_INVALID("{'render': {'camera_keyframes': [{'time': 2.0000002, 'eye': [0, 1, 3], "
                   "'target': [0, 0, 0]}, {'time': 2, 'eye': [0, 1, 3], 'target': [0, 0, 0]}]}, "
                   "'cloths': [{}]}",
                   "t.json: render.camera_keyframes.1.time: must be greater than the previous "
                   "keyframe's time (2.0000002), got 2");
    cvk_scene* scene = PARSE_OK("{'dt': 1e-6, 'frames': 4294967295, 'cloths': [{}]}");
    if (scene)
        CHECK_INT(cvk_scene_get_desc(scene)->frames, 4294967295u);
    cvk_scene_destroy(scene);
}

/* Positions and lengths: finite, and at most 1e5 m (CVK_MAX_COORDINATE) in magnitude. */
static void test_scale_json(void)
{
    const char* far = "must be at most 100000 m from the origin (single-precision metres), got";
    const char* big = "must be at most 100000 m (single-precision metres), got";
    char expected[512];
    snprintf(expected, sizeof expected, "t.json: colliders.0.radius: %s 1e+38", big);
    EXPECT_INVALID("{'colliders': [{'type': 'sphere', 'radius': 1e38}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: colliders.0.center.2: %s -200000", far);
    EXPECT_INVALID("{'colliders': [{'type': 'sphere', 'center': [0, 0, -2e5]}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: colliders.0.half_extents.1: %s 1e+06", big);
    EXPECT_INVALID("{'colliders': [{'type': 'box', 'half_extents': [1, 1e6, 1]}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: colliders.0.b.0: %s 3e+07", far);
    EXPECT_INVALID("{'colliders': [{'type': 'capsule', 'b': [3e7, 0, 0]}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: colliders.0.height: %s 1e+10", big);
    EXPECT_INVALID("{'colliders': [{'type': 'funnel', 'height': 1e10}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: colliders.0.point.1: %s -1e+30", far);
    EXPECT_INVALID("{'colliders': [{'type': 'plane', 'point': [0, -1e30, 0]}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: colliders.0.keyframes.1.translation.0: %s 100001", far);
    EXPECT_INVALID("{'colliders': [{'type': 'plane', 'keyframes': [{'time': 0}, {'time': 1, "
                   "'translation': [100001, 0, 0]}]}], 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: cloths.0.size.0: %s 1e+06", big);
    EXPECT_INVALID("{'cloths': [{'size': [1e6, 1]}]}", expected);
    snprintf(expected, sizeof expected, "t.json: cloths.0.origin.1: %s 200000", far);
    EXPECT_INVALID("{'cloths': [{'origin': [0, 2e5, 0]}]}", expected);
    snprintf(expected, sizeof expected, "t.json: cloths.0.transform.translation.2: %s 1e+20", far);
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'transform': {'translation': [0, 0, 1e20]}}]}", expected);
    snprintf(expected, sizeof expected, "t.json: render.eye.0: %s 1e+09", far);
    EXPECT_INVALID("{'render': {'eye': [1e9, 0, 0], 'target': [0, 0, 0]}, 'cloths': [{}]}", expected);
    snprintf(expected, sizeof expected, "t.json: attachments.0.keyframes.0.translation.1: %s 500000", far);
    EXPECT_INVALID("{'attachments': [{'cloth': 0, 'pins': [[0, 0]], 'keyframes': [{'time': 0, "
                   "'translation': [0, 5e5, 0]}]}], 'cloths': [{}]}", expected);
    /* At the bound itself: taken. */
    cvk_scene* scene = PARSE_OK("{'colliders': [{'type': 'sphere', 'center': [1e5, -1e5, 0], "
                                "'radius': 1e5}], 'cloths': [{'origin': [-1e5, 0, 1e5], 'size': [1e5, 1e5]}]}");
    cvk_scene_destroy(scene);
}

static void test_unknown_keys(void)
{
    EXPECT_INVALID("{'iterationz': 3, 'cloths': [{}]}",
                   "t.json: iterationz: unknown key (expected one of: name, dt, substeps, frames, integrate, "
                   "gravity, damping, solver, cloths, render, collision, colliders, attachments, wind, air_density, instances)");
    EXPECT_INVALID("{'solver': {'iterationz': 3}, 'cloths': [{}]}",
                   "t.json: solver.iterationz: unknown key (expected one of: method, linear, outer_iterations, "
                   "inner_iterations, omega, chebyshev_rho, chebyshev_delay, tolerance, max_iterations, kd, integrator, damping_model, tether_every, strain_limit, fuse)");
    EXPECT_INVALID("{'cloths': [{}, {'colour': [1, 1, 1]}]}",
                   "t.json: cloths.1.colour: unknown key (expected one of: name, grid, size, origin, u_axis, "
                   "v_axis, mesh, transform, rest_scale, mass, density, stiffness, pins, pin_box, color, texture, texture_scale, velocity, tethers, aero, tearing, material)");
    EXPECT_INVALID("{'cloths': [{'stiffness': {'bending': 1}}]}",
                   "t.json: cloths.0.stiffness.bending: unknown key (expected one of: structural, shear, bend)");
}

static void test_wrong_types(void)
{
    EXPECT_INVALID("[{'cloths': [{}]}]", "t.json: the top level must be an object, got an array of 1");
    EXPECT_INVALID("42", "t.json: the top level must be an object, got the number 42");
    EXPECT_INVALID("{}", "t.json: cloths: missing; a scene needs at least one cloth");
    EXPECT_INVALID("{'cloths': []}", "t.json: cloths: a scene needs at least one cloth");
    EXPECT_INVALID("{'cloths': {}}", "t.json: cloths: expected an array of cloth objects, got an object");
    EXPECT_INVALID("{'cloths': [3]}", "t.json: cloths.0: expected an object, got the number 3");
    EXPECT_INVALID("{'name': 3, 'cloths': [{}]}", "t.json: name: expected a string, got the number 3");
    EXPECT_INVALID("{'dt': '0.002', 'cloths': [{}]}", "t.json: dt: expected a number, got the string \"0.002\"");
    EXPECT_INVALID("{'dt': null, 'cloths': [{}]}", "t.json: dt: expected a number, got null");
    EXPECT_INVALID("{'dt': 'abcdefghijklmnopqrstuvwxyz', 'cloths': [{}]}",
                   "t.json: dt: expected a number, got the string \"abcdefghijklmnopqrstu...\"");
    EXPECT_INVALID("{'substeps': 2.5, 'cloths': [{}]}", "t.json: substeps: expected a whole number, got 2.5");
    EXPECT_INVALID("{'substeps': -3, 'cloths': [{}]}", "t.json: substeps: must be at least 1, got -3");
    EXPECT_INVALID("{'substeps': 0, 'cloths': [{}]}", "t.json: substeps: must be at least 1, got 0");
    EXPECT_INVALID("{'frames': 1e10, 'cloths': [{}]}", "t.json: frames: must be at most 4294967295, got 1e+10");
    EXPECT_INVALID("{'frames': true, 'cloths': [{}]}", "t.json: frames: expected a whole number, got true");
    EXPECT_INVALID("{'integrate': 1, 'cloths': [{}]}", "t.json: integrate: expected true or false, got the number 1");
    EXPECT_INVALID("{'gravity': [0, -9.81], 'cloths': [{}]}",
                   "t.json: gravity: expected an array of 3 numbers, got an array of 2");
    EXPECT_INVALID("{'gravity': -9.81, 'cloths': [{}]}", "t.json: gravity: expected an array of 3 numbers, got the number -9.81");
    EXPECT_INVALID("{'gravity': [0, 'down', 0], 'cloths': [{}]}", "t.json: gravity.1: expected a number, got the string \"down\"");
    EXPECT_INVALID("{'solver': [], 'cloths': [{}]}", "t.json: solver: expected an object, got an array of 0");
    EXPECT_INVALID("{'solver': {'linear': 'foo'}, 'cloths': [{}]}",
                   "t.json: solver.linear: unknown linear solver \"foo\" (expected rbgs, jacobi, chebyshev, gs-cpu or cg)");
    EXPECT_INVALID("{'solver': {'method': 'verlet'}, 'cloths': [{}]}",
                   "t.json: solver.method: unknown method \"verlet\" (expected pd, implicit or explicit)");
    EXPECT_INVALID("{'solver': {'linear': 1}, 'cloths': [{}]}", "t.json: solver.linear: expected a string, got the number 1");
    EXPECT_INVALID("{'solver': {'chebyshev_delay': -1}, 'cloths': [{}]}",
                   "t.json: solver.chebyshev_delay: must be at least 0, got -1");
    EXPECT_INVALID("{'solver': {'tether_every': -1}, 'cloths': [{}]}",
                   "t.json: solver.tether_every: must be at least 0, got -1");
    EXPECT_INVALID("{'solver': {'tether_every': 10001}, 'cloths': [{}]}",
                   "t.json: solver.tether_every: must be at most 10000, got 10001");
    EXPECT_INVALID("{'cloths': [{'grid': [10, 10, 10]}]}",
                   "t.json: cloths.0.grid: expected an array of 2 whole numbers, got an array of 3");
    EXPECT_INVALID("{'cloths': [{'grid': [-1, 10]}]}", "t.json: cloths.0.grid.0: must be at least 1, got -1");
    EXPECT_INVALID("{'cloths': [{'stiffness': 5}]}", "t.json: cloths.0.stiffness: expected an object, got the number 5");
    /* [0, 0] is two vertex indices, which a grid does not take. */
    EXPECT_INVALID("{'cloths': [{'pins': [0, 0]}]}",
                   "t.json: cloths.0.pins: a grid cloth takes [i, j] pairs, not vertex indices");
    EXPECT_INVALID("{'cloths': [{'pins': {}}]}",
                   "t.json: cloths.0.pins: expected an array of [i, j] pairs or of vertex indices, got an object");
    EXPECT_INVALID("{'cloths': [{'pins': [[0, 0], [1, 2, 3]]}]}",
                   "t.json: cloths.0.pins.1: expected an array of 2 whole numbers, got an array of 3");
    EXPECT_INVALID("{'cloths': [{'pins': [[0, -1]]}]}", "t.json: cloths.0.pins.0.1: must be at least 0, got -1");
}

static void test_invalid_values_json(void)
{
    EXPECT_INVALID("{'cloths': [{'grid': [0, 100]}]}",
                   "t.json: cloths.0.grid: each dimension must be at least 1, got [0, 100]");
    EXPECT_INVALID("{'cloths': [{'mass': -0.1}]}", "t.json: cloths.0.mass: must be greater than 0, got -0.1");
    EXPECT_INVALID("{'cloths': [{'pins': [[0, 0], [100, 0]]}]}",
                   "t.json: cloths.0.pins.1: [100, 0] is outside the 100 x 100 grid");
    EXPECT_INVALID("{'dt': 0, 'cloths': [{}]}", "t.json: dt: must be greater than 0, got 0");
    EXPECT_INVALID("{'solver': {'omega': 2}, 'cloths': [{}]}",
                   "t.json: solver.omega: must be greater than 0 and less than 2, got 2");
    EXPECT_INVALID("{'cloths': [{}, {'color': [0, 0, 2]}]}", "t.json: cloths.1.color.2: must be between 0 and 1, got 2");
    EXPECT_INVALID("{'cloths': [{'tethers': 0.5}]}",
                   "t.json: cloths.0.tethers: must be 0 (no tethers) or from 1 to 10 (a scale of the rest distance "
                   "to the pins), got 0.5");
    EXPECT_INVALID("{'cloths': [{'tethers': -1}]}",
                   "t.json: cloths.0.tethers: must be 0 (no tethers) or from 1 to 10 (a scale of the rest distance "
                   "to the pins), got -1");
    EXPECT_INVALID("{'cloths': [{'tethers': 11}]}",
                   "t.json: cloths.0.tethers: must be 0 (no tethers) or from 1 to 10 (a scale of the rest distance "
                   "to the pins), got 11");
    EXPECT_INVALID("{'cloths': [{'tethers': true}]}", "t.json: cloths.0.tethers: expected a number, got true");
    EXPECT_INVALID("{'solver': {'method': 'implicit', 'linear': 'cg'}, 'cloths': [{}, {'tethers': 1}]}",
                   "t.json: cloths.1.tethers: the implicit method has no tethers; remove them or use pd");
}

static void test_overrides(void)
{
    const char* const replace[] = {"dt=0.001", "solver.linear=jacobi", "name=sheet", "frames=10", "frames=12"};
    cvk_scene* scene = PARSE_OK_SET("{'dt': 0.002, 'frames': 3, 'cloths': [{}]}", replace);
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK_FLOAT(d->dt, 0.001f);
        CHECK_INT(d->solver.linear, CVK_LINEAR_JACOBI);
        CHECK_STR(d->name, "sheet");
        CHECK_INT(d->frames, 12);
    }
    cvk_scene_destroy(scene);

    const char* const create[] = {"solver.omega=1.5", "cloths.0.stiffness.shear=5", "cloths.0.pins.0=[1, 2]",
                                  "cloths.1={\"mass\": 0.2}", "cloths.2.mass=0.3"};
    scene = PARSE_OK_SET("{'cloths': [{}]}", create);
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK_FLOAT(d->solver.omega, 1.5f);
        CHECK_FLOAT(d->cloths[0].stiffness.shear, 5.0f);
        CHECK_INT(d->cloths[0].pin_count, 1);
        CHECK_INT(d->cloths[0].pins[0][1], 2);
        CHECK_INT(d->cloth_count, 3);
        CHECK_FLOAT(d->cloths[1].mass, 0.2f);
        CHECK_INT(d->cloths[1].grid[0], 100);
        CHECK_FLOAT(d->cloths[2].mass, 0.3f);
    }
    cvk_scene_destroy(scene);
}

/* cvk_scene_get_json: one canonical line, whatever the spacing, key order or spelling of the
   numbers in the file and in the overrides. */
static void test_canonical_json(void)
{
    const char* const sets[] = {"cloths.0.grid=[12,12]", "dt=0.003"};
    const char* const spaced[] = {"cloths.0.grid=[12, 12]", "dt=3e-3"};
    cvk_scene* a = PARSE_OK_SET("{'frames': 3, 'cloths': [{'mass': 0.5}], 'dt': 0.002}", sets);
    cvk_scene* b = PARSE_OK_SET("{ 'cloths' : [ { 'mass' : 5e-1 } ] ,\n 'dt': 2, 'frames': 3 }", spaced);
    if (a && b) {
        CHECK_STR(cvk_scene_get_json(a),
                  "{\"cloths\":[{\"grid\":[12.0,12.0],\"mass\":0.5}],\"dt\":0.0030000000000000001,\"frames\":3.0}");
        CHECK_STR(cvk_scene_get_json(b), cvk_scene_get_json(a));
    }
    cvk_scene_destroy(a);
    cvk_scene_destroy(b);
    CHECK(cvk_scene_get_json(NULL) == NULL);
}

static void test_override_errors(void)
{
    const char* base = "{'cloths': [{}]}";
    const char* grid = "{'cloths': [{'grid': [100, 100]}]}";
    EXPECT_SET_ERROR(base, "dt", "t.json: --set dt: expected key.path=value");
    EXPECT_SET_ERROR(base, "=3", "t.json: --set =3: expected key.path=value");
    EXPECT_SET_ERROR(base, "solver..omega=1", "t.json: --set solver..omega: the key path has an empty part");
    EXPECT_SET_ERROR(base, "dt.=1", "t.json: --set dt.: the key path has an empty part");
    EXPECT_SET_ERROR(base, "cloths.3.grid=[2, 2]",
                     "t.json: --set cloths.3.grid: index 3 is out of range (cloths has 1 element)");
    EXPECT_SET_ERROR("{'cloths': [{}, {}]}", "cloths.5=[2, 2]",
                     "t.json: --set cloths.5: index 5 is out of range (cloths has 2 elements)");
    EXPECT_SET_ERROR(base, "cloths.x=1", "t.json: --set cloths.x: cloths is an array, x is not an index");
    EXPECT_SET_ERROR("{'dt': 0.002, 'cloths': [{}]}", "dt.x=1", "t.json: --set dt.x: dt is not an object or array");
    EXPECT_SET_ERROR("{'cloths': [{'mass': 1}]}", "cloths.0.mass.x.y=1",
                     "t.json: --set cloths.0.mass.x.y: cloths.0.mass is not an object or array");

    /* A bad value that came from --set says so. */
    EXPECT_SET_ERROR(base, "substeps=0", "t.json: substeps (from --set): must be at least 1, got 0");
    EXPECT_SET_ERROR(base, "cloths.0.mass=-1", "t.json: cloths.0.mass (from --set): must be greater than 0, got -1");
    EXPECT_SET_ERROR(base, "cloths.00.mass=-1", "t.json: cloths.0.mass (from --set): must be greater than 0, got -1");
    EXPECT_SET_ERROR(base, "cloths.0={\"mass\": -1}",
                     "t.json: cloths.0.mass (from --set): must be greater than 0, got -1");
    EXPECT_SET_ERROR(grid, "cloths.0.grid.0=0",
                     "t.json: cloths.0.grid (from --set): each dimension must be at least 1, got [0, 100]");
    EXPECT_SET_ERROR(grid, "cloths.0.grid.2=5",
                     "t.json: cloths.0.grid (from --set): expected an array of 2 whole numbers, got an array of 3");
    /* Overrides edit the file's tree, not the defaults: a grid the file lacks starts empty. */
    EXPECT_SET_ERROR(base, "cloths.0.grid.1=8",
                     "t.json: --set cloths.0.grid.1: index 1 is out of range (cloths.0.grid has 0 elements)");
    EXPECT_SET_ERROR(base, "cloths.0.grid.0=8",
                     "t.json: cloths.0.grid (from --set): expected an array of 2 whole numbers, got an array of 1");
    EXPECT_SET_ERROR(base, "dt=NaN", "t.json: dt (from --set): must be a finite number, got NaN");
    EXPECT_SET_ERROR(base, "gravity=[0, NaN, 0]", "t.json: gravity.1 (from --set): must be a finite number, got NaN");
    EXPECT_SET_ERROR(base, "dt=fast", "t.json: dt (from --set): expected a number, got the string \"fast\"");
    EXPECT_SET_ERROR(base, "solver.linear=foo",
                     "t.json: solver.linear (from --set): unknown linear solver \"foo\" (expected rbgs, jacobi, "
                     "chebyshev, gs-cpu or cg)");
    EXPECT_SET_ERROR(base, "solver.iterationz=3",
                     "t.json: solver.iterationz (from --set): unknown key (expected one of: method, linear, "
                     "outer_iterations, inner_iterations, omega, chebyshev_rho, chebyshev_delay, tolerance, "
                     "max_iterations, kd, integrator, damping_model, tether_every, strain_limit, fuse)");
    EXPECT_SET_ERROR(base, "cloths=[]", "t.json: cloths (from --set): a scene needs at least one cloth");
    /* A bad value in the file does not, even when other keys were set. */
    EXPECT_SET_ERROR("{'cloths': [{'mass': -0.1}]}", "frames=10", "t.json: cloths.0.mass: must be greater than 0, got -0.1");
    EXPECT_SET_ERROR("{'cloths': [{'mass': -0.1}]}", "cloths.0.massive=1",
                     "t.json: cloths.0.massive (from --set): unknown key (expected one of: name, grid, size, origin, "
                     "u_axis, v_axis, mesh, transform, rest_scale, mass, density, stiffness, pins, pin_box, color, "
                     "texture, texture_scale, velocity, tethers, aero, tearing, material)");

    cvk_scene* scene = NULL;
    cvk_error err = {0};
    CHECK_INT(cvk_scene_parse("{}", "t.json", NULL, 1, &scene, &err), CVK_ERROR_INVALID_ARGUMENT);
    CHECK_STR(err.message, "cvk_scene_parse: overrides is NULL but override_count is 1");
    CHECK_INT(cvk_scene_parse(NULL, "t.json", NULL, 0, &scene, &err), CVK_ERROR_INVALID_ARGUMENT);
    CHECK_STR(err.message, "cvk_scene_parse: json_text is NULL");
    CHECK_INT(cvk_scene_load("x.json", NULL, 0, NULL, &err), CVK_ERROR_INVALID_ARGUMENT);
    CHECK_STR(err.message, "cvk_scene_load: out_scene is NULL");
}

/* ---- files ---- */

static void expect_load_error_at(const char* file, int line, const char* path, const char* const* sets,
                                 uint32_t set_count, cvk_result result, const char* message)
{
    cvk_scene* scene = NULL;
    cvk_error err = {0};
    cvk_result r = cvk_scene_load(path, sets, set_count, &scene, &err);
    check_int(r, result, path, file, line);
    check_str(err.message, message, path, file, line);
    check_true(scene == NULL, "out_scene is NULL after a failure", file, line);
}

#define EXPECT_LOAD_ERROR(path, result, message) expect_load_error_at(__FILE__, __LINE__, path, NULL, 0, result, message)

static void test_files(void)
{
    EXPECT_LOAD_ERROR("nope.json", CVK_ERROR_IO, "nope.json: cannot open: No such file or directory");

    char dir[] = "/tmp/clothvk-test-scene-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp worked");
        return;
    }
    char path[4][256];
    char expected[512];
    snprintf(path[0], sizeof path[0], "%s/bad.json", dir);
    snprintf(path[1], sizeof path[1], "%s/nan.json", dir);
    snprintf(path[2], sizeof path[2], "%s/my.scene.json", dir);
    snprintf(path[3], sizeof path[3], "%s/empty.json", dir);
    CHECK(write_file(path[0], "{\n  \"dt\": 0.002,\n  \"substeps\" 8,\n  \"cloths\": [{}]\n}\n"));
    CHECK(write_file(path[1], "{\n  \"dt\": NaN,\n  \"cloths\": [{}]\n}\n"));
    CHECK(write_file(path[2], "{ \"cloths\": [{ \"grid\": [4, 4] }] }\n"));
    CHECK(write_file(path[3], ""));

    snprintf(expected, sizeof expected, "%s:3:14: malformed JSON: ':' expected near '8'", path[0]);
    EXPECT_LOAD_ERROR(path[0], CVK_ERROR_PARSE, expected);
    snprintf(expected, sizeof expected, "%s: dt: must be a finite number, got NaN", path[1]);
    EXPECT_LOAD_ERROR(path[1], CVK_ERROR_INVALID_ARGUMENT, expected);
    snprintf(expected, sizeof expected, "%s:1:0: malformed JSON: unexpected token near end of file", path[3]);
    EXPECT_LOAD_ERROR(path[3], CVK_ERROR_PARSE, expected);
    snprintf(expected, sizeof expected, "%s: cannot read: Is a directory", dir);
    EXPECT_LOAD_ERROR(dir, CVK_ERROR_IO, expected);

    /* A sparse file one byte past the bound: refused from its size, before reading. */
    char huge[300];
    snprintf(huge, sizeof huge, "%s/huge.json", dir);
    CHECK(write_file(huge, ""));
    CHECK(truncate(huge, ((off_t)64 << 20) + 1) == 0); /* README: at most 64 MiB */
    snprintf(expected, sizeof expected, "%s: 67108865 bytes; a scene file is at most 67108864", huge);
    EXPECT_LOAD_ERROR(huge, CVK_ERROR_IO, expected);
    CHECK(remove(huge) == 0);

    const char* const sets[] = {"cloths.0.grid.1=8"};
    snprintf(expected, sizeof expected, "%s: --set cloths.3.grid: index 3 is out of range (cloths has 1 element)",
             path[2]);
    expect_load_error_at(__FILE__, __LINE__, path[2], (const char* const[]){"cloths.3.grid=[2, 2]"}, 1,
                         CVK_ERROR_INVALID_ARGUMENT, expected);
    cvk_scene* scene = NULL;
    cvk_error err = {0};
    CHECK_INT(cvk_scene_load(path[2], sets, 1, &scene, &err), CVK_SUCCESS);
    if (scene) {
        CHECK_STR(cvk_scene_get_desc(scene)->name, "my.scene");
        CHECK_INT(cvk_scene_get_desc(scene)->cloths[0].grid[1], 8);
    }
    cvk_scene_destroy(scene);

    for (int i = 0; i < 4; i++)
        CHECK(remove(path[i]) == 0);
    CHECK(rmdir(dir) == 0);
}

static cvk_scene* load_shipped(const char* root, const char* name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/assets/scenes/%s", root, name);
    if (access(path, R_OK) != 0) {
        printf("note: %s is absent; not checked\n", path);
        return NULL;
    }
    cvk_scene* scene = NULL;
    cvk_error err = {0};
    cvk_result r = cvk_scene_load(path, NULL, 0, &scene, &err);
    CHECK_INT(r, CVK_SUCCESS);
    if (r != CVK_SUCCESS)
        printf("    %s\n", err.message);
    return scene;
}

static void test_shipped_scenes(void)
{
    const char* root = getenv("CLOTHVK_SOURCE_ROOT");
    if (!root) {
        printf("note: CLOTHVK_SOURCE_ROOT is not set; shipped scenes not checked\n");
        return;
    }
    cvk_scene* scene = load_shipped(root, "hanging.json");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK_STR(d->name, "hanging");
        CHECK_INT(d->cloths[0].grid[0], 100);
        CHECK_INT(d->cloths[0].pin_count, 2);
        CHECK(d->integrate);
    }
    cvk_scene_destroy(scene);
    scene = load_shipped(root, "enlarged.json");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK_FLOAT(d->cloths[0].rest_scale, 0.2f);
        CHECK(!d->integrate);
        CHECK_INT(d->cloths[0].pin_count, 0);
    }
    cvk_scene_destroy(scene);
    scene = load_shipped(root, "demo.json");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK(!d->render.auto_eye && !d->render.auto_target && !d->render.auto_ground_height);
        CHECK_INT(d->render.samples, 4);
        CHECK_INT(d->render.size[0], 1280);
        CHECK_INT(d->cloths[0].pin_count, 2);
    }
    cvk_scene_destroy(scene);
    scene = load_shipped(root, "hanging-stencil.json");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        CHECK_FLOAT(d->cloths[0].stiffness.shear, 1e6f);
        CHECK_FLOAT(d->cloths[0].stiffness.bend, 1e5f);
    }
    cvk_scene_destroy(scene);
    /* The peers' hanging cloth (README "Accuracy against peers"): its physics exactly. */
    scene = load_shipped(root, "peer-hanging.json");
    if (scene) {
        const cvk_scene_desc* d = cvk_scene_get_desc(scene);
        /* Frames of 1/60 s; its substeps are a solver setting (20 of 1/1200 s). */
        CHECK(fabs(d->dt * d->substeps - 1.0 / 60.0) < 1e-9);
        CHECK_INT(d->substeps, 20);
        CHECK_INT(d->frames, 120);
        const cvk_cloth_desc* c = &d->cloths[0];
        CHECK_INT(c->grid[0], 100);
        CHECK_INT(c->grid[1], 100);
        CHECK_FLOAT(c->mass, 0.1f);
        CHECK_FLOAT(c->stiffness.structural, 1e6f);
        CHECK_FLOAT(c->size[0], 1.0f);
        CHECK_FLOAT(c->size[1], 1.0f);
        CHECK_FLOAT(d->gravity[1], -9.81f);
        CHECK_INT(c->pin_count, 2);
        CHECK(c->pin_count == 2 && c->pins[1][0] == 99 && c->pins[1][1] == 0);
        CHECK_FLOAT(c->tethers, 1.0f);
    }
    cvk_scene_destroy(scene);
    scene = load_shipped(root, "turntable.json");
    if (scene) {
        const cvk_render_desc* r = &cvk_scene_get_desc(scene)->render;
        CHECK(r->wireframe && r->camera_loop);
        CHECK_INT(r->camera_keyframe_count, 9);
        CHECK_FLOAT(r->camera_keyframes[8].time, 4.0f);
    }
    cvk_scene_destroy(scene);
}

int main(void)
{
    test_defaults();
    test_names();
    test_validate_scene();
    test_validate_solver();
    test_validate_cloth_list();
    test_validate_grid();
    test_validate_geometry();
    test_validate_material();
    test_validate_pins();
    test_validate_render();
    test_minimal_json();
    test_render_json();
    test_render_extras_json();
    test_render_looks_json();
    test_full_json();
    test_malformed_json();
    test_nonfinite_json();
    test_numbers_json();
    test_scale_json();
    test_unknown_keys();
    test_wrong_types();
    test_invalid_values_json();
    test_overrides();
    test_canonical_json();
    test_override_errors();
    test_files();
    test_shipped_scenes();
    printf("%d checks, %d failed\n", T.checks, T.failures);
    return T.failures ? 1 : 0;
}
