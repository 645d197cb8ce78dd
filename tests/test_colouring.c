/* Colouring and renumbering: on every scene kind, no spring joins two free particles of one
   colour, each colour is one contiguous range, pinned particles come last, and the padded
   adjacency lists exactly each particle's springs. */
#include "build.h"
#include "harness.h"

typedef struct shape {
    uint32_t w, h;
    bool shear, bend;
    uint32_t pins;
} shape;

static void check_build(const cvk_build* b, const char* label)
{
    CHECK(cvk_build_find_colour_conflict(b) < 0, "%s: spring %lld joins two particles of one colour",
          label, (long long)cvk_build_find_colour_conflict(b));
    CHECK(b->colour_start[0] == 0, "%s: colour 0 starts at %u", label, b->colour_start[0]);
    for (uint32_t c = 0; c < b->colour_count; c++)
        CHECK(b->colour_start[c] <= b->colour_start[c + 1], "%s: colour %u range is reversed", label, c);
    CHECK(b->colour_start[b->colour_count] == b->free_count, "%s: colours cover %u of %u free particles",
          label, b->colour_start[b->colour_count], b->free_count);

    /* internal_of and user_of are inverse permutations */
    bool inverse = true;
    for (uint32_t u = 0; u < b->particle_count; u++)
        inverse = inverse && b->internal_of[u] < b->particle_count && b->user_of[b->internal_of[u]] == u;
    CHECK(inverse, "%s: user_of is not the inverse of internal_of", label);

    /* degree counts every spring with a free end once per free end; padding is inert */
    uint32_t* seen = calloc(b->free_count ? b->free_count : 1, sizeof *seen);
    for (uint32_t s = 0; s < b->spring_count; s++) {
        if (b->springs[s].a < b->free_count)
            seen[b->springs[s].a]++;
        if (b->springs[s].b < b->free_count)
            seen[b->springs[s].b]++;
    }
    bool degrees = true, padding = true, listed = true;
    for (uint32_t p = 0; p < b->free_count; p++) {
        degrees = degrees && seen[p] == b->degree[p];
        for (uint32_t s = 0; s < b->max_degree; s++) {
            size_t e = (size_t)s * b->free_count + p;
            if (s >= b->degree[p])
                padding = padding && b->adj_index[e] == p && b->adj_k[e] == 0.0f;
            else
                listed = listed && b->adj_index[e] != p && b->adj_k[e] > 0.0f && b->adj_rest[e] > 0.0f;
        }
    }
    free(seen);
    CHECK(degrees, "%s: degrees disagree with the spring list", label);
    CHECK(padding, "%s: padding entries are not (self, k = 0)", label);
    CHECK(listed, "%s: a listed spring points at its own particle or has no stiffness", label);
}

static void check_shape(const shape* s)
{
    char label[96];
    snprintf(label, sizeof label, "%ux%u shear=%d bend=%d pins=%u", s->w, s->h, s->shear, s->bend, s->pins);
    uint32_t pins[3][2] = {{0, 0}, {s->w - 1, 0}, {s->w / 2, s->h - 1}};
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = s->w;
    cloth.grid[1] = s->h;
    cloth.stiffness.shear = s->shear ? 1e5f : 0.0f;
    cloth.stiffness.bend = s->bend ? 1e4f : 0.0f;
    cloth.pins = (const uint32_t(*)[2])pins;
    cloth.pin_count = s->pins;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_error err;
    CHECK(cvk_scene_desc_validate(&scene, &err) == CVK_SUCCESS, "%s: %s", label, err.message);
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&scene, &b, &err), err);
    check_build(&b, label);
    uint32_t expected = cvk_grid_colour_count(s->shear, s->bend);
    CHECK(b.colour_count == expected, "%s: %u colours, expected %u", label, b.colour_count, expected);
    uint64_t structural = (uint64_t)(s->w - 1) * s->h + (uint64_t)s->w * (s->h - 1);
    CHECK(b.springs_by_type[CVK_SPRING_STRUCTURAL] == structural, "%s: %llu structural springs, expected %llu",
          label, (unsigned long long)b.springs_by_type[0], (unsigned long long)structural);
    uint64_t shear = s->shear && s->w > 1 && s->h > 1 ? 2ull * (s->w - 1) * (s->h - 1) : 0;
    CHECK(b.springs_by_type[CVK_SPRING_SHEAR] == shear, "%s: %llu shear springs, expected %llu", label,
          (unsigned long long)b.springs_by_type[1], (unsigned long long)shear);
    uint64_t bend = s->bend ? (uint64_t)(s->w > 2 ? s->w - 2 : 0) * s->h + (uint64_t)s->w * (s->h > 2 ? s->h - 2 : 0) : 0;
    CHECK(b.springs_by_type[CVK_SPRING_BEND] == bend, "%s: %llu bend springs, expected %llu", label,
          (unsigned long long)b.springs_by_type[2], (unsigned long long)bend);
    cvk_build_destroy(&b);
}

/* Several cloths of different stencils share the colour ranges. */
static void check_several_cloths(void)
{
    uint32_t pins[1][2] = {{1, 1}};
    cvk_cloth_desc cloths[3] = {cvk_default_cloth_desc(), cvk_default_cloth_desc(), cvk_default_cloth_desc()};
    cloths[0].grid[0] = 9, cloths[0].grid[1] = 6;
    cloths[1].grid[0] = 1, cloths[1].grid[1] = 40; /* a rope */
    cloths[1].stiffness.bend = 1e3f;
    cloths[2].grid[0] = 12, cloths[2].grid[1] = 11;
    cloths[2].stiffness.shear = 1e4f;
    cloths[2].stiffness.bend = 1e3f;
    cloths[2].pins = (const uint32_t(*)[2])pins;
    cloths[2].pin_count = 1;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = cloths;
    scene.cloth_count = 3;
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&scene, &b, &err), err);
    check_build(&b, "three cloths");
    CHECK(b.colour_count == 5, "three cloths: %u colours, expected 5", b.colour_count);
    CHECK(b.particle_count == 9 * 6 + 40 + 12 * 11, "three cloths: %u particles", b.particle_count);
    CHECK(b.free_count == b.particle_count - 1, "three cloths: %u free", b.free_count);
    cvk_build_destroy(&b);
}

/* The checker itself must be able to fail: move one particle into the next colour. */
static void check_detector(void)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = cloth.grid[1] = 6;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    cvk_error err;
    cvk_build b;
    REQUIRE_OK(cvk_build_create(&scene, &b, &err), err);
    CHECK(cvk_build_find_colour_conflict(&b) < 0, "valid colouring flagged");
    b.colour_start[1] += 1; /* the first particle of colour 1 becomes colour 0 */
    CHECK(cvk_build_find_colour_conflict(&b) >= 0, "a broken colouring was not detected");
    cvk_build_destroy(&b);
}

int main(void)
{
    const uint32_t sizes[][2] = {{1, 1}, {1, 30}, {30, 1}, {2, 2}, {3, 3}, {7, 5}, {32, 17}, {100, 100}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        for (int kind = 0; kind < 4; kind++)
            for (uint32_t pins = 0; pins <= 3; pins += 3) {
                shape s = {sizes[i][0], sizes[i][1], kind & 1, (kind & 2) != 0, pins};
                check_shape(&s);
            }
    check_several_cloths();
    check_detector();
    printf("%d checks, %d failed\n", harness_checks, harness_failures);
    return harness_failures ? 1 : 0;
}
