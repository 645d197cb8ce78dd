/* A cloth's texture (cvk_cloth_desc.texture), checked in the image: a flat 1 m grid cloth seen
   obliquely, textured with a 64 x 64 image whose left half (u < 0.5) is red and right half
   blue.
   - where the view projects points of the cloth's u < 0.45 part, the image is red; of its
     u > 0.55 part, blue (the grid's u runs along u_axis, so a mirrored or transposed mapping
     fails);
   - a mesh cloth (OBJ) of the same square maps the texture by the file's texture coordinates,
     which here run the other way (u = 1 at x = -0.5): red on the right, blue on the left;
   - with texture_scale [2, 1] the texture repeats: u in 0.55..0.7 of the cloth (inside the
     second copy's red half, 0.5..0.75) is red, and u in 0.3..0.45 (inside the first copy's
     blue half, 0.25..0.5) blue;
   - the texture's sRGB values are decoded to linear: a cloth textured mid-grey (sRGB 128,
     linear 0.216) draws the pixel the same cloth of colour 0.216 draws, not that of 0.502;
   - a normal map (material.normal_map) of 8 stripes across u, their normals tilted 30° towards
     +u and −u in turn, on the untextured cloth lit from the side along u: the stripes' middles
     alternate in luminance by more than 20 levels, by less than 3 without the map and less
     with normal_strength 0.5 than 1; a normal map that is not an image fails the renderer with
     its key path and stb_image's reason, and no renderer comes back. */
#include <unistd.h>

#include "harness.h"

enum { W = 240, H = 180, T = 64 };

static const float origin[3] = {-0.5f, 1.5f, 0.0f};

static char folder[] = "/tmp/clothvk-texture-XXXXXX";
static char two_colours[600], grey[600], mesh[600], stripes[600];

/* The cloth's square as an OBJ quad grid, 16 x 16 vertices, with texture coordinates
   u = 1 − (x + 0.5), v = 1.5 − y. */
static void write_mesh(const char* path)
{
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", path);
        exit(1);
    }
    for (int j = 0; j < 16; j++)
        for (int i = 0; i < 16; i++)
            fprintf(f, "v %.9g %.9g 0\nvt %.9g %.9g\n", origin[0] + i / 15.0, origin[1] - j / 15.0, 1.0 - i / 15.0,
                    j / 15.0);
    for (int j = 0; j + 1 < 16; j++)
        for (int i = 0; i + 1 < 16; i++) {
            int a = j * 16 + i + 1, b = a + 1, c = a + 16, d = c + 1;
            fprintf(f, "f %d/%d %d/%d %d/%d %d/%d\n", a, a, c, c, d, d, b, b);
        }
    fclose(f);
}

static void write_texture(const char* path, bool halves)
{
    static uint8_t pixels[T * T * 4];
    for (int y = 0; y < T; y++)
        for (int x = 0; x < T; x++) {
            uint8_t* p = &pixels[4 * (y * T + x)];
            bool left = x < T / 2;
            p[0] = halves ? (left ? 220 : 20) : 128;
            p[1] = halves ? 20 : 128;
            p[2] = halves ? (left ? 20 : 220) : 128;
            p[3] = 255;
        }
    cvk_image im = {.pixels = pixels, .width = T, .height = T, .row_bytes = 4 * T};
    cvk_error err;
    REQUIRE_OK(cvk_image_write_png(&im, path, &err), err);
}

/* 8 stripes across u, 8 texels each: tangent-space normals (±sin 30°, 0, cos 30°) in turn. */
static void write_normal_map(const char* path)
{
    static uint8_t pixels[T * T * 4];
    for (int y = 0; y < T; y++)
        for (int x = 0; x < T; x++) {
            uint8_t* p = &pixels[4 * (y * T + x)];
            double tilt = (x / 8) % 2 == 0 ? 0.5 : -0.5;
            p[0] = (uint8_t)lround((tilt + 1.0) * 127.5);
            p[1] = 128;
            p[2] = (uint8_t)lround((0.8660254 + 1.0) * 127.5);
            p[3] = 255;
        }
    cvk_image im = {.pixels = pixels, .width = T, .height = T, .row_bytes = 4 * T};
    cvk_error err;
    REQUIRE_OK(cvk_image_write_png(&im, path, &err), err);
}

typedef struct setup {
    cvk_cloth_desc cloth;
    cvk_scene_desc scene;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
} setup;

/* A cloth in the plane z = 0, u along +x, with `texture` (or none) and `color`, and a normal map
   (or none) of `strength`, lit by the key light from `key`. */
static void setup_lit(setup* s, cvk_context* ctx, const char* texture, float scale_u, const float* color,
                      const char* mesh_file, const char* normal_map, float strength, const float key[3])
{
    memset(s, 0, sizeof *s);
    s->cloth = cvk_default_cloth_desc();
    s->cloth.grid[0] = s->cloth.grid[1] = 16;
    memcpy(s->cloth.origin, origin, sizeof origin);
    memcpy(s->cloth.u_axis, (const float[3]){1, 0, 0}, 3 * sizeof(float));
    memcpy(s->cloth.v_axis, (const float[3]){0, -1, 0}, 3 * sizeof(float));
    s->cloth.mesh = mesh_file;
    s->cloth.texture = texture;
    s->cloth.texture_scale[0] = scale_u;
    s->cloth.normal_map = normal_map;
    s->cloth.normal_strength = strength;
    if (color)
        memcpy(s->cloth.color, color, 3 * sizeof(float));
    s->scene = cvk_default_scene_desc();
    s->scene.integrate = false;
    memset(s->scene.gravity, 0, sizeof s->scene.gravity);
    s->scene.cloths = &s->cloth;
    s->scene.cloth_count = 1;
    cvk_render_desc* r = &s->scene.render;
    r->size[0] = W;
    r->size[1] = H;
    r->ground = false;
    r->shadow_map_size = 256;
    r->auto_eye = r->auto_target = false;
    memcpy(r->eye, (const float[3]){0.3f, 1.3f, 2.2f}, 3 * sizeof(float));
    memcpy(r->target, (const float[3]){0.0f, 1.0f, 0.0f}, 3 * sizeof(float));
    memcpy(r->key.direction, key, 3 * sizeof(float));
    cvk_error err;
    REQUIRE_OK(harness_sim_create(ctx, &s->scene, &s->sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(s->sim, NULL, &s->mesh, &err), err);
    REQUIRE_OK(cvk_renderer_create(s->mesh, r, &s->renderer, &err), err);
    REQUIRE_OK(cvk_renderer_draw(s->renderer, &err), err);
}

static void setup_scene(setup* s, cvk_context* ctx, const char* texture, float scale_u, const float* color,
                        const char* mesh_file)
{
    setup_lit(s, ctx, texture, scale_u, color, mesh_file, NULL, 1.0f, (const float[3]){0.2f, 0.3f, 1.0f});
}

static void teardown(setup* s)
{
    cvk_renderer_destroy(s->renderer);
    cvk_mesh_destroy(s->mesh);
    cvk_sim_destroy(s->sim);
}

/* The pixel where the view projects the cloth point (u, v) (fractions of its size). */
static const uint8_t* pixel_at(const setup* s, double u, double v)
{
    cvk_render_view view = cvk_renderer_get_view(s->renderer);
    const float p[3] = {(float)(origin[0] + u), (float)(origin[1] - v), 0.0f};
    const float* m = view.view_proj;
    double clip[4];
    for (int k = 0; k < 4; k++)
        clip[k] = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
    int x = (int)((clip[0] / clip[3] * 0.5 + 0.5) * W), y = (int)((clip[1] / clip[3] * 0.5 + 0.5) * H);
    x = x < 0 ? 0 : x >= W ? W - 1 : x;
    y = y < 0 ? 0 : y >= H ? H - 1 : y;
    cvk_image im = cvk_renderer_get_image(s->renderer);
    return im.pixels + (size_t)y * im.row_bytes + 4 * (size_t)x;
}

/* Counts the sample points of u in [u0, u1] (and v in 0.1 .. 0.9) that are red (red > 2 blue)
   and blue (blue > 2 red). */
static void count_colours(const setup* s, double u0, double u1, int* red, int* blue, int* total)
{
    *red = *blue = *total = 0;
    for (int j = 0; j <= 8; j++)
        for (int i = 0; i <= 8; i++) {
            const uint8_t* p = pixel_at(s, u0 + (u1 - u0) * i / 8.0, 0.1 + 0.8 * j / 8.0);
            *red += p[0] > 2 * p[2];
            *blue += p[2] > 2 * p[0];
            (*total)++;
        }
}

static void halves(cvk_context* ctx)
{
    setup s;
    setup_scene(&s, ctx, two_colours, 1.0f, NULL, NULL);
    int red, blue, total;
    count_colours(&s, 0.05, 0.45, &red, &blue, &total);
    CHECK(red == total && blue == 0, "left half: %d of %d points red, %d blue", red, total, blue);
    count_colours(&s, 0.55, 0.95, &red, &blue, &total);
    CHECK(blue == total && red == 0, "right half: %d of %d points blue, %d red", blue, total, red);
    teardown(&s);

    setup_scene(&s, ctx, two_colours, 2.0f, NULL, NULL);
    count_colours(&s, 0.55, 0.7, &red, &blue, &total);
    CHECK(red == total, "texture_scale [2, 1]: %d of %d points of u 0.55..0.7 red (the second copy)", red, total);
    count_colours(&s, 0.3, 0.45, &red, &blue, &total);
    CHECK(blue == total, "texture_scale [2, 1]: %d of %d points of u 0.3..0.45 blue", blue, total);
    teardown(&s);

    setup_scene(&s, ctx, two_colours, 1.0f, NULL, mesh);
    count_colours(&s, 0.05, 0.45, &red, &blue, &total);
    CHECK(blue == total, "mesh: %d of %d points of the left half blue", blue, total);
    count_colours(&s, 0.55, 0.95, &red, &blue, &total);
    CHECK(red == total, "mesh: %d of %d points of the right half red", red, total);
    teardown(&s);
}

/* The cloth's middle textured mid-grey (sRGB 128), then untextured of colour 0.216 (linear
   for sRGB 128) and of colour 0.502 (128 / 255 taken as linear), all else equal. */
static void srgb_decoded(cvk_context* ctx)
{
    const float linear[3] = {0.2158605f, 0.2158605f, 0.2158605f};
    const float raw[3] = {0.50196f, 0.50196f, 0.50196f};
    setup s;
    setup_scene(&s, ctx, grey, 1.0f, NULL, NULL);
    int textured = pixel_at(&s, 0.5, 0.5)[1];
    teardown(&s);
    setup_scene(&s, ctx, NULL, 1.0f, linear, NULL);
    int plain = pixel_at(&s, 0.5, 0.5)[1];
    teardown(&s);
    setup_scene(&s, ctx, NULL, 1.0f, raw, NULL);
    int undecoded = pixel_at(&s, 0.5, 0.5)[1];
    teardown(&s);
    CHECK(abs(textured - plain) <= 3, "textured grey %d against the plain cloth of linear 0.216: %d", textured,
          plain);
    CHECK(undecoded - textured > 20, "linear 0.5 draws %d, not far above the texture's %d", undecoded, textured);
}

/* How much the luminance of the stripes' middles (u = (k + 0.5) / 8, v = 0.5) alternates: the
   mean of the even stripes' minus the odd ones', in levels. */
static double stripe_contrast(cvk_context* ctx, const char* normal_map, float strength)
{
    const float key[3] = {1.0f, 0.2f, 0.6f};
    setup s;
    setup_lit(&s, ctx, NULL, 1.0f, NULL, NULL, normal_map, strength, key);
    double sum[2] = {0.0, 0.0};
    for (int k = 0; k < 8; k++) {
        const uint8_t* p = pixel_at(&s, (k + 0.5) / 8.0, 0.5);
        sum[k % 2] += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    }
    teardown(&s);
    return fabs(sum[0] - sum[1]) / 4.0;
}

static void normal_map(cvk_context* ctx)
{
    double bumped = stripe_contrast(ctx, stripes, 1.0f);
    double half = stripe_contrast(ctx, stripes, 0.5f);
    double flat = stripe_contrast(ctx, NULL, 1.0f);
    CHECK(bumped > 20.0, "the striped normal map's stripes differ by %.1f levels", bumped);
    CHECK(flat < 3.0, "without the normal map the same places differ by %.1f levels", flat);
    CHECK(half < bumped - 3.0 && half > flat, "normal_strength 0.5: %.1f levels, 1: %.1f, none: %.1f", half,
          bumped, flat);
    printf("normal map: stripes differ by %.1f levels (strength 1), %.1f (0.5), %.1f without\n", bumped, half, flat);

    /* Not an image: the OBJ file. */
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.normal_map = mesh;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.integrate = false;
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.render.size[0] = scene.render.size[1] = 64;
    cvk_error err;
    cvk_sim* sim;
    cvk_mesh* m;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &m, &err), err);
    /* Anything but NULL, so that the failure must clear it. */
    cvk_renderer* renderer = (cvk_renderer*)m;
    cvk_result r = cvk_renderer_create(m, &scene.render, &renderer, &err);
    /* The whole message: the reason in brackets is stb_image's for a file of no format it
       knows (stbi_info_from_memory on the OBJ text). */
    char expected[800];
    snprintf(expected, sizeof expected, "cloths.0.material.normal_map: %s: not an image stb_image "
             "can read (unknown image type)", mesh);
    CHECK(r == CVK_ERROR_INVALID_ARGUMENT && strcmp(err.message, expected) == 0,
          "a normal map that is not an image: %d, \"%s\"", (int)r, err.message);
    CHECK(renderer == NULL, "a renderer came back from the failed cvk_renderer_create");
    if (r == CVK_SUCCESS)
        cvk_renderer_destroy(renderer);
    cvk_mesh_destroy(m);
    cvk_sim_destroy(sim);
}

int main(void)
{
    if (!mkdtemp(folder)) {
        perror("mkdtemp");
        return 1;
    }
    snprintf(two_colours, sizeof two_colours, "%s/halves.png", folder);
    snprintf(grey, sizeof grey, "%s/grey.png", folder);
    snprintf(mesh, sizeof mesh, "%s/square.obj", folder);
    snprintf(stripes, sizeof stripes, "%s/stripes.png", folder);
    write_normal_map(stripes);
    write_mesh(mesh);
    write_texture(two_colours, true);
    write_texture(grey, false);
    cvk_context* ctx = harness_context();
    halves(ctx);
    srgb_decoded(ctx);
    normal_map(ctx);
    unlink(stripes);
    unlink(two_colours);
    unlink(grey);
    unlink(mesh);
    rmdir(folder);
    return harness_finish(ctx);
}
