/* No acne, speckles or dark fringes on lit cloth: cloths placed where shadow maps and smooth
   normals are at their worst, drawn with 1 and 4 samples per pixel, and on each image a count
   of the isolated dark pixels on the cloth — pixels far darker than their cloth neighbourhood
   that are not part of a connected dark feature (a shadow's edge, a fold's line):
   - a cloth folded over itself with a 1.5 cm radius, its upper layer shadowing the lower,
     seen from above, from the side of the fold, end-on and from below, and lit at a grazing
     angle;
   - a cloth seen nearly edge-on, and a cloth lit at grazing angles (the light 3° and 10°
     off its plane, from either face), flat and gently curved: nothing there can shadow the
     cloth, so also no pixel amid it may be more than 10 % off the median of its 5 x 5
     neighbourhood (acne in bands, where no pixel stands alone).
   A pixel counts when it and its 8 neighbours are cloth, it is darker than 0.6 of the median of
   the cloth pixels in its 5 x 5 neighbourhood, and the 8-connected group of pixels darker than
   0.85 of that median around it has at most 2 pixels. Set CLOTHVK_TEST_IMAGES to a folder to
   keep the images (isolated pixels marked green in a copy, NAME-marked.png). */
#include "harness.h"

#include <math.h>

enum { W = 240, H = 180 };

static const float background[3] = {0.1f, 0.2f, 0.45f};
static const float red[3] = {0.75f, 0.18f, 0.12f};

/* ---- scenes: one static cloth, placed particle by particle ---- */

typedef struct placed {
    uint32_t nu, nv;
    float* xyz;                  /* 3 floats per particle, i fastest */
} placed;

static placed placed_make(uint32_t nu, uint32_t nv)
{
    placed p = {nu, nv, calloc((size_t)nu * nv * 3, sizeof(float))};
    if (!p.xyz)
        exit(1);
    return p;
}

/* Particle (i, j) of a 1.2 m x 0.4 m cloth (1 cm spacing along i) folded over itself: flat at
   y = 1 up to x = 0.7, half a circle of radius r, then back above itself. */
static placed folded_cloth(float r)
{
    placed p = placed_make(121, 41);
    const float fold = 0.7f, pi = 3.14159265f;
    for (uint32_t j = 0; j < p.nv; j++)
        for (uint32_t i = 0; i < p.nu; i++) {
            float s = 0.01f * (float)i, x, y;
            if (s <= fold) {
                x = s, y = 1.0f;
            } else if (s <= fold + pi * r) {
                float a = (s - fold) / r;
                x = fold + r * sinf(a), y = 1.0f + r * (1.0f - cosf(a));
            } else {
                x = fold - (s - fold - pi * r), y = 1.0f + 2.0f * r;
            }
            float* q = &p.xyz[3 * ((size_t)j * p.nu + i)];
            q[0] = x - 0.5f, q[1] = y, q[2] = 0.01f * (float)j - 0.2f;
        }
    return p;
}

/* A 0.8 m square cloth in the plane z = 0 (x right, y up), bent into an arc of `bend` radians
   about the vertical axis (0: flat). */
static placed wall_cloth(float bend)
{
    placed p = placed_make(81, 81);
    for (uint32_t j = 0; j < p.nv; j++)
        for (uint32_t i = 0; i < p.nu; i++) {
            float s = 0.01f * (float)i - 0.4f, x = s, z = 0.0f;
            if (bend > 0.0f) {
                float radius = 0.8f / bend, a = s / radius;
                x = radius * sinf(a), z = radius * (1.0f - cosf(a));
            }
            float* q = &p.xyz[3 * ((size_t)j * p.nu + i)];
            q[0] = x, q[1] = 1.0f + 0.01f * (float)j - 0.4f, q[2] = z;
        }
    return p;
}

typedef struct view_desc {
    const char* name;
    float eye[3], target[3], key[3];
    bool smooth;                 /* nothing in view can shadow the cloth: its shading is smooth */
} view_desc;

/* Draws `cloth` with `samples` per pixel into `out` (W x H x 4 bytes). */
static void render(cvk_context* ctx, const placed* cloth, const view_desc* v, uint32_t samples, uint8_t* out)
{
    cvk_cloth_desc c = cvk_default_cloth_desc();
    c.grid[0] = cloth->nu;
    c.grid[1] = cloth->nv;
    memcpy(c.color, red, sizeof red);
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.integrate = false;
    memset(scene.gravity, 0, sizeof scene.gravity);
    scene.cloths = &c;
    scene.cloth_count = 1;
    cvk_render_desc* r = &scene.render;
    r->size[0] = W;
    r->size[1] = H;
    r->samples = samples;
    r->ground = false;
    r->auto_eye = r->auto_target = false;
    memcpy(r->eye, v->eye, sizeof r->eye);
    memcpy(r->target, v->target, sizeof r->target);
    memcpy(r->key.direction, v->key, sizeof r->key.direction);
    memcpy(r->background, background, sizeof r->background);
    cvk_error err;
    cvk_sim* sim;
    cvk_mesh* mesh;
    cvk_renderer* renderer;
    REQUIRE_OK(harness_sim_create(ctx, &scene, &sim, &err), err);
    uint64_t n = (uint64_t)cloth->nu * cloth->nv;
    REQUIRE_OK(cvk_sim_write_positions(sim, cloth->xyz, n, &err), err);
    REQUIRE_OK(cvk_mesh_create(sim, NULL, &mesh, &err), err);
    REQUIRE_OK(cvk_renderer_create(mesh, r, &renderer, &err), err);
    REQUIRE_OK(cvk_renderer_draw(renderer, &err), err);
    cvk_image im = cvk_renderer_get_image(renderer);
    for (uint32_t y = 0; y < H; y++)
        memcpy(out + (size_t)y * W * 4, im.pixels + (size_t)y * im.row_bytes, (size_t)W * 4);
    cvk_renderer_destroy(renderer);
    cvk_mesh_destroy(mesh);
    cvk_sim_destroy(sim);
}

/* ---- the count ---- */

static double luminance(const uint8_t* p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

static int compare_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

typedef struct count {
    uint32_t cloth, dark, isolated;
    uint32_t uneven;             /* pixels amid cloth more than 10 % off their 5 x 5 median */
} count;

/* Luminance of the cloth pixels (negative elsewhere). */
static double lum[H][W];

/* The 8-connected pixels darker than `threshold` around (x, y), up to `limit`. */
static int dark_group(int x, int y, double threshold, int limit)
{
    int at[16][2] = {{x, y}}, size = 1;
    for (int k = 0; k < size && size <= limit; k++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int xx = at[k][0] + dx, yy = at[k][1] + dy;
                if (xx < 0 || xx >= W || yy < 0 || yy >= H || lum[yy][xx] < 0.0 || lum[yy][xx] >= threshold)
                    continue;
                bool known = false;
                for (int j = 0; j < size && !known; j++)
                    known = at[j][0] == xx && at[j][1] == yy;
                if (!known && size <= limit)
                    at[size][0] = xx, at[size][1] = yy, size++;
            }
    return size;
}

/* Marks the isolated dark pixels in `mark` (W x H) and counts them: darker than 0.6 of the
   median of the cloth in their 5 x 5 neighbourhood, with at most one neighbour (8-connected,
   and so on) darker than 0.85 of that median. A shadow's edge or a line along a fold is a
   longer group; a speckle stands alone in light around it. */
static count count_isolated(const uint8_t* im, uint8_t* mark)
{
    uint8_t bg[3];
    for (int k = 0; k < 3; k++) {
        double s = background[k] <= 0.0031308f ? 12.92 * background[k] : 1.055 * pow(background[k], 1.0 / 2.4) - 0.055;
        bg[k] = (uint8_t)lround(s * 255.0);
    }
    count n = {0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t* p = im + ((size_t)y * W + x) * 4;
            bool cloth = abs(p[0] - bg[0]) > 2 || abs(p[1] - bg[1]) > 2 || abs(p[2] - bg[2]) > 2;
            lum[y][x] = cloth ? luminance(p) : -1.0;
            n.cloth += cloth;
        }
    for (int y = 2; y < H - 2; y++)
        for (int x = 2; x < W - 2; x++) {
            bool inner = true;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    inner = inner && lum[y + dy][x + dx] >= 0.0;
            if (!inner)
                continue;
            double around[25];
            int m = 0;
            for (int dy = -2; dy <= 2; dy++)
                for (int dx = -2; dx <= 2; dx++)
                    if (lum[y + dy][x + dx] >= 0.0)
                        around[m++] = lum[y + dy][x + dx];
            qsort(around, (size_t)m, sizeof around[0], compare_double);
            double median = m % 2 ? around[m / 2] : 0.5 * (around[m / 2 - 1] + around[m / 2]);
            if (m == 25 && fabs(lum[y][x] - median) > 0.1 * median)
                n.uneven++;
            if (!(lum[y][x] < 0.6 * median))
                continue;
            n.dark++;
            if (dark_group(x, y, 0.85 * median, 2) <= 2) {
                mark[y * W + x] = 1;
                n.isolated++;
            }
        }
    return n;
}

static void keep_image(const uint8_t* im, const uint8_t* mark, const char* name)
{
    const char* folder = getenv("CLOTHVK_TEST_IMAGES");
    if (!folder)
        return;
    char path[512];
    cvk_error err;
    snprintf(path, sizeof path, "%s/%s.png", folder, name);
    cvk_image plain = {.pixels = (uint8_t*)im, .width = W, .height = H, .row_bytes = 4 * W};
    REQUIRE_OK(cvk_image_write_png(&plain, path, &err), err);
    static uint8_t copy[W * H * 4];
    memcpy(copy, im, sizeof copy);
    for (int i = 0; i < W * H; i++)
        if (mark[i])
            copy[4 * i] = 0, copy[4 * i + 1] = 255, copy[4 * i + 2] = 0;
    cvk_image out = {.pixels = copy, .width = W, .height = H, .row_bytes = 4 * W};
    snprintf(path, sizeof path, "%s/%s-marked.png", folder, name);
    REQUIRE_OK(cvk_image_write_png(&out, path, &err), err);
}

static uint32_t total_isolated;

static void check_view(cvk_context* ctx, const placed* cloth, const view_desc* v)
{
    static const uint32_t sample_counts[2] = {1, 4};
    for (int s = 0; s < 2; s++) {
        static uint8_t im[W * H * 4], mark[W * H];
        render(ctx, cloth, v, sample_counts[s], im);
        memset(mark, 0, sizeof mark);
        count n = count_isolated(im, mark);
        char name[128];
        snprintf(name, sizeof name, "acne-%s-%ux", v->name, sample_counts[s]);
        keep_image(im, mark, name);
        printf("%-28s %ux: %5u cloth pixels, %4u dark, %3u isolated, %4u uneven\n", v->name, sample_counts[s],
               n.cloth, n.dark, n.isolated, n.uneven);
        CHECK(n.cloth > W * H / 50, "%s, %ux: only %u pixels show cloth", v->name, sample_counts[s], n.cloth);
        CHECK(n.isolated == 0, "%s, %ux: %u isolated dark pixels on the cloth", v->name, sample_counts[s],
              n.isolated);
        /* Acne also comes as bands (moire) that no pixel stands out of alone. */
        CHECK(!v->smooth || n.uneven == 0, "%s, %ux: %u pixels amid the cloth are more than 10 %% off their "
              "neighbourhood's median", v->name, sample_counts[s], n.uneven);
        total_isolated += n.isolated;
    }
}

int main(void)
{
    cvk_context* ctx = harness_context();
    placed fold = folded_cloth(0.015f);
    static const view_desc fold_views[] = {
        {"fold-above", {0.75f, 1.55f, 0.55f}, {0.1f, 1.0f, 0.0f}, {0.45f, 1.0f, 0.6f}, false},
        {"fold-side", {0.75f, 1.12f, 0.35f}, {0.2f, 1.01f, 0.0f}, {0.45f, 1.0f, 0.6f}, false},
        {"fold-end-on", {0.95f, 1.1f, 0.0f}, {0.2f, 1.0f, 0.0f}, {0.3f, 1.0f, 0.2f}, false},
        {"fold-grazing-light", {0.75f, 1.55f, 0.55f}, {0.1f, 1.0f, 0.0f}, {-1.0f, 0.1f, 0.3f}, false},
        {"fold-under", {0.7f, 0.6f, 0.6f}, {0.1f, 1.0f, 0.0f}, {0.3f, -1.0f, 0.5f}, false},
    };
    for (size_t i = 0; i < sizeof fold_views / sizeof fold_views[0]; i++)
        check_view(ctx, &fold, &fold_views[i]);
    free(fold.xyz);

    placed flat = wall_cloth(0.0f), curved = wall_cloth(1.2f);
    /* tan 3° ≈ 0.052, tan 10° ≈ 0.176: the light that far off the wall's plane. */
    static const view_desc wall_views[] = {
        {"edge-on", {1.2f, 1.1f, 0.15f}, {0.0f, 1.0f, 0.0f}, {0.3f, 0.6f, 1.0f}, true},
        {"grazing-3-front", {0.6f, 1.3f, 2.2f}, {0.0f, 1.0f, 0.0f}, {1.0f, 0.3f, 0.055f}, true},
        {"grazing-10-back", {-0.6f, 1.3f, -2.2f}, {0.0f, 1.0f, 0.0f}, {1.0f, 0.3f, -0.184f}, true},
    };
    for (size_t i = 0; i < sizeof wall_views / sizeof wall_views[0]; i++)
        check_view(ctx, &flat, &wall_views[i]);
    static const view_desc curved_views[] = {
        {"curved-grazing", {0.3f, 1.3f, -2.2f}, {0.0f, 1.0f, 0.2f}, {1.0f, 0.25f, 0.1f}, true},
        {"curved-edge-on", {2.4f, 1.05f, 0.7f}, {0.0f, 1.0f, 0.2f}, {0.2f, 0.5f, -1.0f}, true},
    };
    for (size_t i = 0; i < sizeof curved_views / sizeof curved_views[0]; i++)
        check_view(ctx, &curved, &curved_views[i]);
    free(flat.xyz);
    free(curved.xyz);
    printf("%u isolated dark pixels in all\n", total_isolated);
    return harness_finish(ctx);
}
