/* The scene keys of a mesh cloth: mesh, transform, density, pins as vertex indices and pin_box,
   in programmatic descriptions, in JSON and through overrides; and a relative mesh path, which
   names a file next to the scene file. Every message is compared exactly. */
#include "scene_checks.h"

#include <math.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- validation of programmatic descriptions ---- */

/* A mesh cloth: its shape comes from the file, so its grid keys are not looked at. */
static void test_validate_mesh(void)
{
    static const uint32_t pairs[][2] = {{0, 0}};
    static const uint32_t vertices[] = {0, 4000000000u}; /* the range is checked when the mesh is read */
    fixture f;
    fixture_init(&f);
    f.cloths[0].mesh = "poncho.obj";
    f.cloths[0].grid[0] = 0;
    f.cloths[0].size[1] = NAN;
    memset(f.cloths[0].u_axis, 0, sizeof f.cloths[0].u_axis);
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].mesh = "";
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.mesh: must name a mesh file, got an empty string");

    fixture_init(&f);
    f.cloths[0].mesh = "poncho.obj";
    f.cloths[0].pin_vertices = vertices;
    f.cloths[0].pin_vertex_count = 2;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].pin_vertices = NULL;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pins: pin_vertices is NULL but pin_vertex_count is 2");
    f.cloths[0].pin_vertex_count = 0;
    f.cloths[0].pins = pairs;
    f.cloths[0].pin_count = 1;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pins: a mesh cloth takes vertex indices (file order), not [i, j] pairs");

    fixture_init(&f);
    f.cloths[0].pin_vertices = vertices;
    f.cloths[0].pin_vertex_count = 1;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pins: a grid cloth takes [i, j] pairs, not vertex indices");
}

static void test_validate_transform(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].mesh = "poncho.obj";
    f.cloths[0].transform.scale[0] = -2.0f; /* a mirror */
    f.cloths[0].transform.rotation[0] = 3.0f; /* normalised when the mesh is read */
    f.cloths[0].transform.rotation[2] = 4.0f;
    f.cloths[0].transform.translation[1] = -7.0f;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].transform.scale[1] = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.transform.scale.1: must not be zero, got 0");
    f.cloths[0].transform.scale[1] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.transform.scale.1: must be a finite number, got nan");

    fixture_init(&f);
    memset(f.cloths[0].transform.rotation, 0, sizeof f.cloths[0].transform.rotation);
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.transform.rotation: must not be zero, got [0, 0, 0, 0]");
    f.cloths[0].transform.rotation[3] = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.transform.rotation.3: must be a finite number, got inf");

    fixture_init(&f);
    f.cloths[0].transform.translation[2] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.transform.translation.2: must be a finite number, got nan");
}

static void test_validate_density(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].density = -1.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.density: must be at least 0, got -1");
    f.cloths[0].density = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.density: must be a finite number, got nan");
    /* A density replaces the mass, which is then not looked at. */
    f.cloths[0].density = 0.2f;
    f.cloths[0].mass = 0.0f;
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].density = 0.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.mass: must be greater than 0, got 0");

    fixture_init(&f);
    f.cloths[0].grid[0] = 1;
    f.cloths[0].grid[1] = 50;
    f.cloths[0].density = 0.2f;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.0.density: a 1 x 50 grid is a rope, with no area for a density; give its mass instead");
    f.cloths[0].grid[0] = 50;
    f.cloths[0].grid[1] = 1;
    EXPECT_DESC_INVALID(&f.scene,
                        "cloths.0.density: a 50 x 1 grid is a rope, with no area for a density; give its mass instead");
    f.cloths[0].mesh = "poncho.obj"; /* the grid is not looked at */
    EXPECT_DESC_VALID(&f.scene);
}

static void test_validate_pin_box(void)
{
    fixture f;
    fixture_init(&f);
    f.cloths[0].pin_box = (cvk_box3){.min = {0.0f, 0.5f, 0.0f}, .max = {1.0f, 0.2f, 1.0f}};
    EXPECT_DESC_VALID(&f.scene); /* not looked at without use_pin_box */
    f.cloths[0].use_pin_box = true;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pin_box: min 0.5 is above max 0.2 on axis y");
    f.cloths[0].pin_box.max[1] = 0.5f; /* a flat box holds what lies in its plane */
    EXPECT_DESC_VALID(&f.scene);
    f.cloths[0].pin_box.min[2] = 2.0f;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pin_box: min 2 is above max 1 on axis z");
    f.cloths[0].pin_box.min[0] = NAN;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pin_box.0.0: must be a finite number, got nan");
    f.cloths[0].pin_box.min[0] = 0.0f;
    f.cloths[0].pin_box.max[2] = INFINITY;
    EXPECT_DESC_INVALID(&f.scene, "cloths.0.pin_box.1.2: must be a finite number, got inf");
}

/* ---- JSON and overrides ---- */

static void test_mesh_json(void)
{
    cvk_scene* scene = PARSE_OK("{'cloths': [{'mesh': 'meshes/poncho.obj', 'transform': {'scale': [1, 2, 3],"
                                "   'rotation': [0, 0, 1, 0], 'translation': [4, 5, 6]},"
                                "   'density': 0.15, 'pins': [0, 7, 3], 'pin_box': [[-1, 0.5, -2], [1, 2, 3]]},"
                                "  {'mesh': '/data/flag.obj', 'transform': {'scale': 2.5}},"
                                "  {'grid': [4, 4], 'pins': [[0, 3]], 'pin_box': [[0, 0, 0], [1, 1, 1]]}]}");
    if (!scene)
        return;
    const cvk_cloth_desc* c = cvk_scene_get_desc(scene)->cloths;
    /* Text in memory has no folder: a relative path is kept as written. */
    CHECK_STR(c[0].mesh, "meshes/poncho.obj");
    for (int k = 0; k < 3; k++) {
        CHECK_FLOAT(c[0].transform.scale[k], (float)(k + 1));
        CHECK_FLOAT(c[0].transform.translation[k], (float)(k + 4));
    }
    CHECK_FLOAT(c[0].transform.rotation[0], 0.0f);
    CHECK_FLOAT(c[0].transform.rotation[2], 1.0f);
    CHECK_FLOAT(c[0].density, 0.15f);
    CHECK_INT(c[0].pin_vertex_count, 3);
    if (c[0].pin_vertex_count == 3) {
        CHECK_INT(c[0].pin_vertices[0], 0);
        CHECK_INT(c[0].pin_vertices[1], 7);
        CHECK_INT(c[0].pin_vertices[2], 3);
    }
    CHECK(c[0].pins == NULL);
    CHECK_INT(c[0].pin_count, 0);
    CHECK(c[0].use_pin_box);
    CHECK_FLOAT(c[0].pin_box.min[1], 0.5f);
    CHECK_FLOAT(c[0].pin_box.min[2], -2.0f);
    CHECK_FLOAT(c[0].pin_box.max[0], 1.0f);
    CHECK_FLOAT(c[0].pin_box.max[2], 3.0f);

    CHECK_STR(c[1].mesh, "/data/flag.obj");
    for (int k = 0; k < 3; k++)
        CHECK_FLOAT(c[1].transform.scale[k], 2.5f);
    CHECK_FLOAT(c[1].transform.rotation[0], 1.0f); /* the rest of the transform keeps its defaults */
    CHECK_FLOAT(c[1].density, 0.0f);

    CHECK_STR(c[2].mesh, NULL);
    CHECK_INT(c[2].pin_count, 1);
    CHECK_INT(c[2].pin_vertex_count, 0);
    CHECK(c[2].use_pin_box);
    CHECK_FLOAT(c[2].pin_box.max[1], 1.0f);
    cvk_scene_destroy(scene);
}

static void test_mesh_json_errors(void)
{
    EXPECT_INVALID("{'cloths': [{'mesh': 3}]}", "t.json: cloths.0.mesh: expected a string, got the number 3");
    EXPECT_INVALID("{'cloths': [{'mesh': ''}]}", "t.json: cloths.0.mesh: must name a mesh file, got an empty string");
    EXPECT_INVALID("{'cloths': [{'transform': 3}]}", "t.json: cloths.0.transform: expected an object, got the number 3");
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'transform': {'shear': 1}}]}",
                   "t.json: cloths.0.transform.shear: unknown key (expected one of: scale, rotation, translation)");
    EXPECT_INVALID("{'cloths': [{'transform': {'scale': 'big'}}]}",
                   "t.json: cloths.0.transform.scale: expected a number or an array of 3 numbers, got the string \"big\"");
    EXPECT_INVALID("{'cloths': [{'transform': {'scale': [1, 2]}}]}",
                   "t.json: cloths.0.transform.scale: expected an array of 3 numbers, got an array of 2");
    EXPECT_INVALID("{'cloths': [{'transform': {'scale': NaN}}]}",
                   "t.json: cloths.0.transform.scale: must be a finite number, got NaN");
    /* One number is named by its own key path, not as the first of three. */
    EXPECT_INVALID("{'cloths': [{'transform': {'scale': 0}}]}",
                   "t.json: cloths.0.transform.scale: must not be zero, got 0");
    EXPECT_INVALID("{'cloths': [{'transform': {'scale': [1, 0, 1]}}]}",
                   "t.json: cloths.0.transform.scale.1: must not be zero, got 0");
    EXPECT_INVALID("{'colliders': [{'type': 'mesh', 'file': 'a.obj', 'transform': {'scale': 0}}], "
                   "'cloths': [{}]}",
                   "t.json: colliders.0.transform.scale: must not be zero, got 0");
    EXPECT_INVALID("{'cloths': [{'transform': {'scale': -1e39}}]}",
                   "t.json: cloths.0.transform.scale: is too large for single precision (at most "
                   "3.4028235e+38 in magnitude), got -1e+39");
    EXPECT_INVALID("{'cloths': [{'transform': {'rotation': [1, 0, 0]}}]}",
                   "t.json: cloths.0.transform.rotation: expected an array of 4 numbers, got an array of 3");
    EXPECT_INVALID("{'cloths': [{'transform': {'rotation': [0, 0, 0, 0]}}]}",
                   "t.json: cloths.0.transform.rotation: must not be zero, got [0, 0, 0, 0]");
    EXPECT_INVALID("{'cloths': [{'transform': {'translation': [0, Infinity, 0]}}]}",
                   "t.json: cloths.0.transform.translation.1: must be a finite number, got Infinity");
    EXPECT_INVALID("{'cloths': [{'density': -0.5}]}", "t.json: cloths.0.density: must be at least 0, got -0.5");
    EXPECT_INVALID("{'cloths': [{'density': 'heavy'}]}",
                   "t.json: cloths.0.density: expected a number, got the string \"heavy\"");
    EXPECT_INVALID("{'cloths': [{'grid': [1, 20], 'size': [0, 1], 'density': 0.2}]}",
                   "t.json: cloths.0.density: a 1 x 20 grid is a rope, with no area for a density; give its mass "
                   "instead");
    EXPECT_INVALID("{'cloths': [{'density': 0.2, 'mass': 0}, {'mass': 0}]}",
                   "t.json: cloths.1.mass: must be greater than 0, got 0");
}

static void test_mesh_pins_json(void)
{
    /* The first element says which form the array has; an element of the other form is named. */
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'pins': [0, 1, 2, [3, 4]]}]}",
                   "t.json: cloths.0.pins.3: expected a vertex index (a whole number, like element 0), got an "
                   "array of 2");
    EXPECT_INVALID("{'cloths': [{'pins': [[0, 0], 5]}]}",
                   "t.json: cloths.0.pins.1: expected an array of 2 whole numbers, got the number 5");
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'pins': [0, -1]}]}", "t.json: cloths.0.pins.1: must be at least 0, got -1");
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'pins': [1.5]}]}",
                   "t.json: cloths.0.pins.0: expected a whole number, got 1.5");
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'pins': ['top']}]}",
                   "t.json: cloths.0.pins.0: expected a whole number, got the string \"top\"");
    EXPECT_INVALID("{'cloths': [{'mesh': 'a.obj', 'pins': [[0, 0]]}]}",
                   "t.json: cloths.0.pins: a mesh cloth takes vertex indices (file order), not [i, j] pairs");
    EXPECT_INVALID("{'cloths': [{'pins': [0, 1]}]}",
                   "t.json: cloths.0.pins: a grid cloth takes [i, j] pairs, not vertex indices");
    cvk_scene* scene = PARSE_OK("{'cloths': [{'mesh': 'a.obj', 'pins': []}]}");
    if (scene)
        CHECK_INT(cvk_scene_get_desc(scene)->cloths[0].pin_vertex_count, 0);
    cvk_scene_destroy(scene);

    EXPECT_INVALID("{'cloths': [{'pin_box': [0, 0, 0]}]}",
                   "t.json: cloths.0.pin_box: expected [[xmin, ymin, zmin], [xmax, ymax, zmax]], got an array of 3");
    EXPECT_INVALID("{'cloths': [{'pin_box': {'min': [0, 0, 0]}}]}",
                   "t.json: cloths.0.pin_box: expected [[xmin, ymin, zmin], [xmax, ymax, zmax]], got an object");
    EXPECT_INVALID("{'cloths': [{'pin_box': [[0, 0], [1, 1, 1]]}]}",
                   "t.json: cloths.0.pin_box.0: expected an array of 3 numbers, got an array of 2");
    EXPECT_INVALID("{'cloths': [{'pin_box': [[0, 0.5, 0], [1, 0.2, 1]]}]}",
                   "t.json: cloths.0.pin_box: min 0.5 is above max 0.2 on axis y");
    EXPECT_INVALID("{'cloths': [{'pin_box': [[0, 0, 0], [NaN, 1, 1]]}]}",
                   "t.json: cloths.0.pin_box.1.0: must be a finite number, got NaN");
}

static void test_mesh_overrides(void)
{
    const char* const sets[] = {"cloths.0.mesh=meshes/flag.obj", "cloths.0.pins.0=4", "cloths.0.pins.1=9",
                                "cloths.0.transform.scale=2", "cloths.0.pin_box=[[0, 0, 0], [1, 1, 1]]",
                                "cloths.0.density=0.3"};
    cvk_scene* scene = PARSE_OK_SET("{'cloths': [{}]}", sets);
    if (scene) {
        const cvk_cloth_desc* c = cvk_scene_get_desc(scene)->cloths;
        CHECK_STR(c->mesh, "meshes/flag.obj");
        CHECK_INT(c->pin_vertex_count, 2);
        if (c->pin_vertex_count == 2)
            CHECK_INT(c->pin_vertices[1], 9);
        CHECK_FLOAT(c->transform.scale[2], 2.0f);
        CHECK(c->use_pin_box);
        CHECK_FLOAT(c->pin_box.max[0], 1.0f);
        CHECK_FLOAT(c->density, 0.3f);
    }
    cvk_scene_destroy(scene);

    const char* base = "{'cloths': [{}]}";
    EXPECT_SET_ERROR(base, "cloths.0.transform.scale=0",
                     "t.json: cloths.0.transform.scale (from --set): must not be zero, got 0");
    EXPECT_SET_ERROR(base, "cloths.0.transform.skew=1",
                     "t.json: cloths.0.transform.skew (from --set): unknown key (expected one of: scale, rotation, "
                     "translation)");
    EXPECT_SET_ERROR("{'cloths': [{'mesh': 'a.obj', 'pins': [0, 1]}]}", "cloths.0.pins.2=[0, 0]",
                     "t.json: cloths.0.pins.2 (from --set): expected a vertex index (a whole number, like element 0), "
                     "got an array of 2");
}

/* A relative mesh path in a scene file names a file next to the scene file, whatever the
   working directory; so does one set with an override. */
static void test_mesh_paths(void)
{
    char dir[] = "/tmp/clothvk-test-mesh-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp worked");
        return;
    }
    char sub[64], path[128], expected[512], cwd[4096];
    snprintf(sub, sizeof sub, "%s/sub", dir);
    snprintf(path, sizeof path, "%s/scene.json", sub);
    CHECK(mkdir(sub, 0700) == 0);
    CHECK(write_file(path, "{\"cloths\": [{\"mesh\": \"meshes/poncho.obj\"}, {\"mesh\": \"/abs/flag.obj\"},"
                           " {\"mesh\": \"../up.obj\"}]}\n"));
    const char* const sets[] = {"cloths.3.mesh=dress.obj"};
    cvk_scene* scene = NULL;
    cvk_error err = {0};
    CHECK_INT(cvk_scene_load(path, sets, 1, &scene, &err), CVK_SUCCESS);
    if (scene) {
        const cvk_cloth_desc* c = cvk_scene_get_desc(scene)->cloths;
        snprintf(expected, sizeof expected, "%s/meshes/poncho.obj", sub);
        CHECK_STR(c[0].mesh, expected);
        CHECK_STR(c[1].mesh, "/abs/flag.obj");
        snprintf(expected, sizeof expected, "%s/../up.obj", sub);
        CHECK_STR(c[2].mesh, expected);
        snprintf(expected, sizeof expected, "%s/dress.obj", sub);
        CHECK_STR(c[3].mesh, expected);
    }
    cvk_scene_destroy(scene);

    /* A scene path relative to the working directory gives mesh paths relative to it too. */
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    CHECK(chdir(dir) == 0);
    scene = NULL;
    CHECK_INT(cvk_scene_load("sub/scene.json", NULL, 0, &scene, &err), CVK_SUCCESS);
    if (scene)
        CHECK_STR(cvk_scene_get_desc(scene)->cloths[0].mesh, "sub/meshes/poncho.obj");
    cvk_scene_destroy(scene);
    CHECK(chdir("sub") == 0);
    scene = NULL;
    CHECK_INT(cvk_scene_load("scene.json", NULL, 0, &scene, &err), CVK_SUCCESS);
    if (scene)
        CHECK_STR(cvk_scene_get_desc(scene)->cloths[0].mesh, "meshes/poncho.obj");
    cvk_scene_destroy(scene);
    CHECK(chdir(cwd) == 0);

    CHECK(remove(path) == 0);
    CHECK(rmdir(sub) == 0);
    CHECK(rmdir(dir) == 0);
}

int main(void)
{
    test_validate_mesh();
    test_validate_transform();
    test_validate_density();
    test_validate_pin_box();
    test_mesh_json();
    test_mesh_json_errors();
    test_mesh_pins_json();
    test_mesh_overrides();
    test_mesh_paths();
    printf("%d checks, %d failed\n", T.checks, T.failures);
    return T.failures ? 1 : 0;
}
