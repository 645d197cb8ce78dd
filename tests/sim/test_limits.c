/* The largest values the scene format accepts, taken through cvk_sim_create (the loader calls
   them valid; creation multiplies them into plan, query and buffer sizes and into the solve's
   diagonal): each is refused with its exact message and result, never a crash or a wrapped
   allocation. Under AddressSanitizer (scripts/test-sanitize.sh) a wrapped size would be an
   overflow report. */
#include <string.h>

#include "harness.h"

typedef struct limit_case {
    const char* name;
    uint32_t substeps, outer, inner;
    double dt;
    float mass;
    float structural;
    cvk_result result;
    const char* message;
} limit_case;

static const limit_case cases[] = {
    {"every count at its bound", 10000, 100, 100, 1.0 / 60, 0.1f, 1e4f, CVK_ERROR_INVALID_ARGUMENT,
     "substeps: 10000 substeps × 20000 operations per substep are 200000000 operations per "
     "frame; a frame records at most 1000000 (fewer substeps, sweeps or colours)"},
    /* Accepted: 1/h² = 1e10 and m/h² = 8.3e7 are well inside float. */
    {"a small step with the most substeps", 10000, 1, 1, 1e-5, 0.1f, 1e4f, CVK_SUCCESS, ""},
    {"the largest mass", 1, 1, 1, 1.0 / 60, 3.4e38f, 1e4f, CVK_ERROR_INVALID_ARGUMENT,
     "cloths.0.mass: a particle of 2.83333e+37 kg with a step of 0.0166667 s has m/h² = "
     "1.02e+41 kg/s², outside [1e-30, 1e+30] where single-precision solves hold it"},
    {"the smallest mass", 1, 1, 1, 1.0 / 60, 1e-45f, 1e4f, CVK_ERROR_INVALID_ARGUMENT,
     "cloths.0.mass: a particle of 0 kg with a step of 0.0166667 s has m/h² = 0 kg/s², "
     "outside [1e-30, 1e+30] where single-precision solves hold it"},
    {"the largest stiffness", 1, 1, 1, 1.0 / 60, 0.1f, 3.4e38f, CVK_ERROR_INVALID_ARGUMENT,
     "cloths.0.stiffness: a particle's springs sum to 6.8e+38 N/m; with m/h² = 30 kg/s² its "
     "row's diagonal exceeds 1e+30, beyond what single-precision solves hold"},
};

static void run_case(cvk_context* ctx, const limit_case* c)
{
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.grid[0] = 4;
    cloth.grid[1] = 3;
    cloth.mass = c->mass;
    cloth.stiffness.structural = c->structural;
    cvk_scene_desc scene = cvk_default_scene_desc();
    scene.cloths = &cloth;
    scene.cloth_count = 1;
    scene.dt = c->dt;
    scene.substeps = c->substeps;
    scene.solver.outer_iterations = c->outer;
    scene.solver.inner_iterations = c->inner;
    cvk_error err = {.message = ""};
    cvk_sim* sim = NULL;
    cvk_result r = harness_sim_create(ctx, &scene, &sim, &err);
    CHECK(r == c->result && (r == CVK_SUCCESS) == (sim != NULL), "%s: got %s (expected %s)", c->name, cvk_result_name(r),
          cvk_result_name(c->result));
    CHECK(r == CVK_SUCCESS || strcmp(err.message, c->message) == 0, "%s: message\n  %s\nexpected\n  %s", c->name,
          err.message, c->message);
    cvk_sim_destroy(sim);
}

int main(void)
{
    cvk_context* ctx = harness_context();
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        run_case(ctx, &cases[i]);
    return harness_finish(ctx);
}
