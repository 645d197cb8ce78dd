/* clothvk-sim: runs a scene headless and prints statistics. */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "clothvk.h"
#include "common.h"
#include "bake.h"
#include "obj.h"
#include "pc2.h"
#include "wedge.h"

static const char tool[] = "clothvk-sim";

static void usage(FILE* out)
{
    fprintf(out,
            "usage: clothvk-sim SCENE [--frames N] [--set key.path=value]... [--json]\n"
            "                   [--dump FILE.csv] [--obj DIR] [--pc2 FILE.pc2]\n"
            "                   [--bake DIR | --resume DIR] [--every K] [--plan]\n"
            "       clothvk-sim SCENE --wedge key.path=v1,v2,... [--wedges FILE]... -o DIR\n"
            "                   [--jobs N | --wedge-index K | --wedge-count] [--wedge-preview]\n"
            "       clothvk-sim --wedge-gather DIR\n"
            "  --frames N     frames to simulate (default: the scene's \"frames\")\n"
            "  --set k=v      override a scene key by its dotted JSON path, value as JSON\n"
            "  --json         print one JSON object of statistics\n"
            "  --dump FILE    write final positions as x,y,z lines (cloth by cloth, row-major)\n"
            "  --obj DIR      write frames as Wavefront OBJ files DIR/frame_0000.obj, ... (the\n"
            "                 folder is created if missing): every cloth an object with vertex\n"
            "                 positions (m), normals and its triangles\n"
            "  --pc2 FILE     write the frames as one PC2 point cache (Blender's Mesh Cache\n"
            "                 modifier, 3ds Max and Maya read it), and beside it the rest mesh\n"
            "                 as an OBJ with the same vertex order: FILE with its extension\n"
            "                 replaced by .obj\n"
            "  --bake DIR     write the exact state as DIR/frame_0000.snap, ... (numbered as\n"
            "                 --obj) after DIR/cache.json, which holds the scene (docs/tools.md)\n"
            "  --resume DIR   continue the bake in DIR from its last complete frame to N frames\n"
            "                 (default: the bake's), bit for bit as an uninterrupted bake\n"
            "  --every K      with --obj, --pc2 or --bake: file or sample i holds the state after\n"
            "                 i*K frames, for every i*K <= N (i = 0: before the first step; the\n"
            "                 last is --dump's state when K divides N); default 1\n"
            "  --plan         print the step plan and exit\n"
            "  --workgroup-size N  compute workgroup size (default: the library's choice)\n"
            "  --max-workgroups N  workgroups per dispatch (default: the library's choice)\n"
            "  --search-lanes N    accepted for older scripts; no effect\n"
            "  --wedge k=v1,v2,...  vary a key over values (JSON, as --set takes them); the\n"
            "                 variants are the product of every --wedge (docs/tools.md, Wedges)\n"
            "  --wedges FILE  explicit variants: a JSON list of objects key.path -> value\n"
            "  -o DIR         the wedge's folder: DIR/v0000/ ... per variant, DIR/wedges.csv,\n"
            "                 DIR/contact-sheet.png\n"
            "  --jobs N       run the variants N at a time on this machine (default 1), then\n"
            "                 gather them\n"
            "  --wedge-index K  run variant K only (a Slurm array task: scripts/slurm-wedge.sh)\n"
            "  --wedge-count  print how many variants there are and exit\n"
            "  --wedge-limit N  refuse more than N variants (default 1000)\n"
            "  --wedge-time-limit S  stop a variant after S seconds (a timed-out row)\n"
            "  --wedge-preview  draw each variant's last frame (DIR/vNNNN/last.png)\n"
            "  --wedge-bake   bake each variant (DIR/vNNNN/bake)\n"
            "  --wedge-gather DIR  write DIR/wedges.csv and DIR/contact-sheet.png from the\n"
            "                 variant folders\n"
            "  --version      print the version and exit\n"
            "environment: CLOTHVK_DEVICE (device index or name), CLOTHVK_VALIDATION=1\n");
}

typedef struct options {
    const char* scene;
    bool frames_set;
    uint32_t frames;
    app_overrides overrides;
    bool json;
    const char* dump;
    const char* obj;
    const char* pc2;
    uint32_t every; /* 0: not given (1) */
    uint32_t every_given; /* 0: not given */
    const char* bake;
    const char* resume;
    bool plan;
    uint32_t workgroup_size;
    uint32_t max_workgroups;
    uint32_t search_lanes;
    app_wedge_options wedge;
    app_wedge_run* wedge_run; /* set while one variant of a wedge runs */
} options;

/* The options that only make sense together, and --dump's target: checked before any work. */
static int check_wedge_options(const options* o)
{
    const app_wedge_options* w = &o->wedge;
    if (!w->axis_count && !w->file) {
        app_error(tool, "the wedge options need --wedge key.path=v1,v2,... or --wedges FILE");
        return APP_EXIT_BAD_INPUT;
    }
    if (o->json || o->dump || o->obj || o->pc2 || o->bake || o->resume || o->every || o->plan) {
        app_error(tool, "a wedge writes each variant's statistics into its folder: --json, "
                  "--dump, --obj, --pc2, --bake, --resume, --every and --plan do not go with "
                  "--wedge (see --wedge-bake)");
        return APP_EXIT_BAD_INPUT;
    }
    if (w->index_set + w->jobs_set + w->count > 1) {
        app_error(tool, "--wedge-index, --jobs and --wedge-count: give one");
        return APP_EXIT_BAD_INPUT;
    }
    if (!w->count && !w->out) {
        app_error(tool, "a wedge needs an output folder (-o DIR)");
        return APP_EXIT_BAD_INPUT;
    }
    return APP_EXIT_OK;
}

static int check_options(options* o)
{
    if (app_wedge_requested(&o->wedge) || o->wedge.out)
        return check_wedge_options(o);
    if (o->every && !o->obj && !o->pc2 && !o->bake && !o->resume) {
        app_error(tool, "--every needs --obj DIR, --pc2 FILE or --bake DIR (it says which frames "
                  "go out)");
        return APP_EXIT_BAD_INPUT;
    }
    if (o->bake && o->resume) {
        app_error(tool, "--bake and --resume: give one (--resume continues a bake)");
        return APP_EXIT_BAD_INPUT;
    }
    if (o->pc2 && o->resume) {
        app_error(tool, "--pc2 and --resume: a point cache holds a whole run; write it with "
                  "--bake or a plain run");
        return APP_EXIT_BAD_INPUT;
    }
    if (o->dump && !app_output_option_ok(tool, "--dump", o->dump))
        return APP_EXIT_BAD_INPUT;
    o->every_given = o->every;
    if (!o->every)
        o->every = 1;
    return APP_EXIT_OK;
}

static int take_wedge(void* user, const char* option, const char* value)
{
    options* o = user;
    if (!value) {
        app_error(tool, "%s: expected key.path=v1,v2,...", option);
        return APP_EXIT_BAD_INPUT;
    }
    return app_wedge_add_axis(&o->wedge, tool, value);
}

/* Returns APP_EXIT_OK or APP_EXIT_BAD_INPUT; `done` is set for --help and --version. */
static int parse_args(int argc, char** argv, options* o, bool* done)
{
    const app_option table[] = {
        {"--frames", NULL, APP_OPTION_U32, .number = &o->frames, .min = 0, .max = 100000000,
         .flag = &o->frames_set},
        {"--set", NULL, APP_OPTION_SET, .overrides = &o->overrides},
        {"--dump", NULL, APP_OPTION_PATH, .path = &o->dump, .expected = "a file name",
         .empty_ok = true},
        {"--obj", NULL, APP_OPTION_PATH, .path = &o->obj, .expected = "an output folder"},
        {"--pc2", NULL, APP_OPTION_PATH, .path = &o->pc2, .expected = "a file name"},
        {"--bake", NULL, APP_OPTION_PATH, .path = &o->bake, .expected = "a bake folder"},
        {"--resume", NULL, APP_OPTION_PATH, .path = &o->resume, .expected = "a bake folder"},
        {"--every", NULL, APP_OPTION_U32, .number = &o->every, .min = 1, .max = 100000000},
        {"--workgroup-size", NULL, APP_OPTION_U32, .number = &o->workgroup_size, .min = 1,
         .max = 1024},
        {"--max-workgroups", NULL, APP_OPTION_U32, .number = &o->max_workgroups, .min = 1,
         .max = UINT32_MAX},
        {"--search-lanes", NULL, APP_OPTION_U32, .number = &o->search_lanes, .min = 1,
         .max = 1024},
        {"--json", NULL, APP_OPTION_FLAG, .flag = &o->json},
        {"--wedge", NULL, APP_OPTION_OTHER, .take = take_wedge},
        {"--wedges", NULL, APP_OPTION_PATH, .path = &o->wedge.file, .expected = "a JSON file"},
        {"-o", "--output", APP_OPTION_PATH, .path = &o->wedge.out, .expected = "an output folder"},
        {"--jobs", NULL, APP_OPTION_U32, .number = &o->wedge.jobs, .min = 1, .max = 1024,
         .flag = &o->wedge.jobs_set},
        {"--wedge-index", NULL, APP_OPTION_U32, .number = &o->wedge.index, .min = 0,
         .max = UINT32_MAX - 1, .flag = &o->wedge.index_set},
        {"--wedge-count", NULL, APP_OPTION_FLAG, .flag = &o->wedge.count},
        {"--wedge-limit", NULL, APP_OPTION_U32, .number = &o->wedge.limit, .min = 1,
         .max = 1000000},
        {"--wedge-time-limit", NULL, APP_OPTION_U32, .number = &o->wedge.time_limit_s, .min = 1,
         .max = 100000000},
        {"--wedge-preview", NULL, APP_OPTION_FLAG, .flag = &o->wedge.preview},
        {"--wedge-bake", NULL, APP_OPTION_FLAG, .flag = &o->wedge.bake},
        {"--plan", NULL, APP_OPTION_FLAG, .flag = &o->plan},
    };
    app_command_line line = {tool, usage, table, sizeof table / sizeof table[0], o, NULL};
    int status = app_read_command_line(&line, argc, argv, &o->scene, done);
    return status != APP_EXIT_OK || *done ? status : check_options(o);
}

typedef struct run_totals {
    uint32_t frames;
    double wall_ms;
    uint32_t timed_frames;
    double gpu_ms;
    double pass_ms[CVK_MAX_PASSES];
    bool diverged; /* the library stopped the run; the report says where and when */
    bool timed_out; /* a wedge variant passed its time limit (between frames) */
} run_totals;

/* Steps `frames` frames. With OBJ or PC2 output, file or sample i holds the state after
   i·every frames, for every i·every <= frames: the start, then one state per K simulated
   frames up to the last, which (K dividing the frames) is the state --dump writes. A bake
   starts at its last complete frame and writes its own frames; writing is not timed. */
/* Ctrl-C (or SIGTERM) stops the run before the next frame: the OBJ files and bake frames
   written so far are whole (each is renamed into place complete), and the dump and the point
   cache, written only by a run that finished, are not written. */
static int run_frames(cvk_sim* sim, uint32_t frames, app_obj_frames* out, app_pc2* pc2,
                      uint32_t every, app_bake* bake, double deadline_ms, run_totals* t)
{
    cvk_error err;
    for (uint32_t f = bake ? bake->first : 0;; f++) {
        if (out && f % every == 0 && !app_obj_frames_write(out, f / every, f))
            return APP_EXIT_FAILURE;
        if (pc2 && f % every == 0 && !app_pc2_write(pc2))
            return APP_EXIT_FAILURE;
        if (bake && !app_bake_frame(bake, f))
            return APP_EXIT_FAILURE;
        if (f == frames)
            return APP_EXIT_OK;
        if (app_interrupted()) {
            app_error(tool, "interrupted after %u of %u frames; the files written are complete",
                      f, frames);
            return APP_EXIT_FAILURE;
        }
        double t0 = app_now_ms();
        if (deadline_ms > 0 && t0 > deadline_ms) {
            t->timed_out = true; /* the statistics of the frames run are still reported */
            return APP_EXIT_OK;
        }
        cvk_result r = cvk_sim_step(sim, 1, &err);
        if (r == CVK_ERROR_DIVERGED) {
            t->wall_ms += app_now_ms() - t0;
            t->frames++;
            t->diverged = true;
            return APP_EXIT_OK;
        }
        if (r != CVK_SUCCESS) {
            app_error(tool, "%s", err.message);
            return APP_EXIT_FAILURE;
        }
        t->wall_ms += app_now_ms() - t0;
        t->frames++;
        cvk_sim_stats timing;
        cvk_sim_get_timing(sim, &timing);
        if (timing.gpu_ms_per_frame < 0)
            continue;
        t->timed_frames++;
        t->gpu_ms += timing.gpu_ms_per_frame;
        for (uint32_t p = 0; p < timing.pass_count && p < CVK_MAX_PASSES; p++)
            t->pass_ms[p] += timing.passes[p].gpu_ms;
    }
}

/* A float printed with the digits it has: 0.002, not 0.00200000009. */
static json_t* float_json(float v)
{
    char text[32];
    double shortest = v;
    for (int digits = 1; digits <= 9; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, (double)v);
        if ((float)strtod(text, NULL) == v) {
            shortest = strtod(text, NULL);
            break;
        }
    }
    return json_real(shortest);
}

/* Whether a cloth of the scene tears (its springs may break). */
static bool scene_tears(const cvk_scene_desc* scene)
{
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        if (scene->cloths[c].tearing.max_stretch > 0.0f)
            return true;
    return false;
}

static json_t* real_or_null(double v, bool valid)
{
    return valid && isfinite(v) ? json_real(v) : json_null();
}

/* The solver's settings as the run used them (the defaults resolved), each method's own. */
static json_t* solver_json(const cvk_scene_desc* scene)
{
    json_t* solver = json_pack("{sssssisiso}", "method", cvk_method_name(scene->solver.method),
                               "linear", cvk_linear_solver_name(scene->solver.linear),
                               "outer_iterations", (json_int_t)scene->solver.outer_iterations,
                               "inner_iterations", (json_int_t)scene->solver.inner_iterations,
                               "omega", float_json(scene->solver.omega));
    cvk_solver_desc resolved = cvk_solver_desc_resolve(&scene->solver); /* what ran */
    if (solver && scene->solver.method == CVK_METHOD_IMPLICIT) {
        json_object_set_new(solver, "tolerance", float_json(resolved.tolerance));
        json_object_set_new(solver, "max_iterations", json_integer(resolved.max_iterations));
        json_object_set_new(solver, "kd", float_json(scene->solver.kd));
    }
    if (solver && scene->solver.method == CVK_METHOD_PD) { /* 0: every sweep runs */
        json_object_set_new(solver, "tolerance", float_json(resolved.tolerance));
        json_object_set_new(solver, "max_iterations", json_integer(resolved.max_iterations));
    }
    if (solver && scene->solver.method == CVK_METHOD_EXPLICIT) {
        cvk_integrator integrator = scene->solver.integrator ? scene->solver.integrator
                                                             : CVK_INTEGRATOR_EULER;
        cvk_damping_model model = scene->solver.damping_model ? scene->solver.damping_model
                                                              : CVK_DAMPING_SPRING;
        json_object_del(solver, "linear");
        json_object_del(solver, "outer_iterations");
        json_object_del(solver, "inner_iterations");
        json_object_del(solver, "omega");
        json_object_set_new(solver, "integrator", json_string(cvk_integrator_name(integrator)));
        json_object_set_new(solver, "damping_model", json_string(cvk_damping_model_name(model)));
        json_object_set_new(solver, "kd", float_json(scene->solver.kd));
    }
    return solver;
}

/* The linear solver's iterations (pd: sweeps), for the methods that solve one. */
static json_t* linear_solver_json(const cvk_scene_desc* scene, const cvk_sim_stats* st)
{
    cvk_solver_desc resolved = cvk_solver_desc_resolve(&scene->solver); /* what ran */
    json_t* linear = json_object();
    json_object_set_new(linear, "iterations_last_frame", json_integer(st->solver_iterations));
    json_object_set_new(linear, "iterations_per_substep",
                        json_real((double)st->solver_iterations_total /
                                  ((double)st->frames * scene->substeps + (st->frames == 0))));
    if (scene->solver.method == CVK_METHOD_IMPLICIT)
        json_object_set_new(linear, "breakdowns", json_integer(st->solver_breakdowns));
    else if (resolved.tolerance > 0.0f) /* the last check's measure (solver.tolerance) */
        json_object_set_new(linear, "residual_last", json_real(st->solver_residual));
    return linear;
}

static json_t* contacts_json(const cvk_sim_stats* st)
{
    json_t* contacts = json_object();
    json_object_set_new(contacts, "colliders", json_integer((json_int_t)st->collider_contacts));
    json_object_set_new(contacts, "self", json_integer((json_int_t)st->self_contacts));
    json_object_set_new(contacts, "max_penetration", json_real(st->max_penetration));
    json_object_set_new(contacts, "intersecting_pairs",
                        json_integer((json_int_t)st->intersecting_pairs));
    json_object_set_new(contacts, "searches", json_integer((json_int_t)st->contact_searches));
    json_object_set_new(contacts, "held", json_integer((json_int_t)st->contact_held));
    json_object_set_new(contacts, "held_fraction", json_real(st->contact_held_fraction));
    json_object_set_new(contacts, "cut_short", json_boolean(st->contact_cut));
    json_object_set_new(contacts, "crowded", json_integer((json_int_t)st->contact_crowded));
    return contacts;
}

/* Each pass's GPU time per frame (null when the device gave no timestamps) and dispatches. */
static json_t* passes_json(const cvk_sim_stats* st, const run_totals* t)
{
    bool timed = t->timed_frames > 0;
    json_t* passes = json_array();
    for (uint32_t p = 0; p < st->pass_count; p++)
        json_array_append_new(passes,
                              json_pack("{ssso si}", "name", st->passes[p].name, "gpu_ms",
                                        real_or_null(t->pass_ms[p] / t->timed_frames, timed),
                                        "dispatches", (json_int_t)st->passes[p].dispatches));
    return passes;
}

static json_t* memory_json(const cvk_context* ctx)
{
    cvk_context_info info = cvk_context_get_info(ctx);
    json_t* memory = json_object();
    json_object_set_new(memory, "device_bytes", json_integer((json_int_t)info.device_bytes));
    json_object_set_new(memory, "device_peak_bytes",
                        json_integer((json_int_t)info.device_peak_bytes));
    json_object_set_new(memory, "host_peak_rss_bytes", json_integer((json_int_t)app_peak_rss()));
    return memory;
}

static json_t* notes_json(const cvk_sim* sim)
{
    json_t* notes = json_array();
    for (uint32_t i = 0; i < cvk_sim_note_count(sim); i++)
        json_array_append_new(notes, json_string(cvk_sim_note(sim, i)));
    return notes;
}

static json_t* stats_json(const cvk_scene_desc* scene, const cvk_context* ctx, const cvk_sim* sim,
                          const cvk_sim_stats* st, const run_totals* t)
{
    bool timed = t->timed_frames > 0;
    json_t* springs = json_pack("{sIsIsI}", "structural", (json_int_t)st->springs[0], "shear",
                                (json_int_t)st->springs[1], "bend", (json_int_t)st->springs[2]);
    json_t* residuals = json_pack("{sfsfsf}", "structural", st->residual_per_type[0], "shear",
                                  st->residual_per_type[1], "bend", st->residual_per_type[2]);
    json_t* root = json_object();
    json_object_set_new(root, "scene", json_string(scene->name ? scene->name : "scene"));
    json_object_set_new(root, "device", json_string(cvk_context_get_info(ctx).device_name));
    json_object_set_new(root, "particles", json_integer((json_int_t)st->particles));
    json_object_set_new(root, "pinned", json_integer((json_int_t)st->pinned));
    json_object_set_new(root, "springs", springs);
    json_object_set_new(root, "colours", json_integer(st->colours));
    json_object_set_new(root, "frames", json_integer(t->frames));
    json_object_set_new(root, "substeps", json_integer(scene->substeps));
    json_object_set_new(root, "dt", float_json(scene->dt));
    json_object_set_new(root, "solver", solver_json(scene));
    json_object_set_new(root, "residual", json_real(st->residual));
    json_object_set_new(root, "residual_normalized", json_real(st->residual_normalized));
    json_object_set_new(root, "residual_per_type", residuals);
    json_object_set_new(root, "max_stretch", real_or_null(st->max_stretch, true));
    json_object_set_new(root, "p99_stretch", real_or_null(st->p99_stretch, true));
    json_object_set_new(root, "torn_springs", json_integer((json_int_t)st->torn_springs));
    json_object_set_new(root, "nan_count", json_integer((json_int_t)st->nan_count));
    json_object_set_new(root, "diverged", json_boolean(st->diverged));
    if (st->diverged) {
        json_object_set_new(root, "diverged_frame", json_integer((json_int_t)st->diverged_frame));
        json_object_set_new(root, "diverged_cloth", json_integer(st->diverged_cloth));
        json_object_set_new(root, "diverged_reason",
                            json_string(st->diverged_nonfinite ? "non-finite" : "run-away"));
    }
    if (scene->solver.method != CVK_METHOD_EXPLICIT) /* pd: sweeps */
        json_object_set_new(root, "linear_solver", linear_solver_json(scene, st));
    if (scene->collider_count > 0 || scene->collision.self)
        json_object_set_new(root, "contacts", contacts_json(st));
    json_object_set_new(root, "gpu_ms_per_frame", real_or_null(t->gpu_ms / t->timed_frames, timed));
    json_object_set_new(root, "wall_ms_per_frame",
                        real_or_null(t->wall_ms / t->frames, t->frames > 0));
    json_object_set_new(root, "dispatches_per_frame", json_integer(st->dispatches_per_frame));
    json_object_set_new(root, "dispatches_per_substep", json_integer(st->dispatches_per_substep));
    json_object_set_new(root, "passes", passes_json(st, t));
    json_object_set_new(root, "memory", memory_json(ctx));
    json_object_set_new(root, "validation_messages",
                        json_integer(cvk_context_validation_message_count(ctx)));
    json_object_set_new(root, "notes", notes_json(sim));
    return root;
}

static bool write_json(FILE* file, void* user)
{
    return json_dumpf(user, file, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9)) ==
               0 && fputc('\n', file) != EOF;
}

/* The --json object on stdout, or (a wedge variant) into its file. */
static int print_json(const options* o, const cvk_scene_desc* scene, const cvk_context* ctx,
                      const cvk_sim* sim, const cvk_sim_stats* st, const run_totals* t)
{
    json_t* root = stats_json(scene, ctx, sim, st, t);
    int status = APP_EXIT_OK;
    char message[600];
    if (o->wedge_run && !app_write_atomic(o->wedge_run->stats_path, write_json, root, message,
                                          sizeof message)) {
        app_error(tool, "%s", message);
        status = APP_EXIT_FAILURE;
    } else if (!o->wedge_run) {
        char* text = json_dumps(root, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(9));
        if (text)
            printf("%s\n", text);
        free(text);
    }
    json_decref(root);
    return status;
}

static void print_summary(const cvk_scene_desc* scene, const cvk_context* ctx,
                          const cvk_sim_stats* st, const run_totals* t)
{
    printf("%s: %u frames of %u substeps (dt %g s) on %s\n", scene->name ? scene->name : "scene",
           t->frames, scene->substeps, scene->dt, cvk_context_get_info(ctx).device_name);
    bool explicit_method = scene->solver.method == CVK_METHOD_EXPLICIT;
    printf("  %llu particles (%llu pinned), %llu springs, %u colours, %s%s%s ",
           (unsigned long long)st->particles, (unsigned long long)st->pinned,
           (unsigned long long)(st->springs[0] + st->springs[1] + st->springs[2]), st->colours,
           cvk_method_name(scene->solver.method), explicit_method ? "" : "/",
           explicit_method ? "" : cvk_linear_solver_name(scene->solver.linear));
    cvk_solver_desc resolved = cvk_solver_desc_resolve(&scene->solver); /* what ran */
    if (scene->solver.method == CVK_METHOD_IMPLICIT)
        printf("to %g, at most %u\n", resolved.tolerance, resolved.max_iterations);
    else if (scene->solver.method == CVK_METHOD_PD && resolved.tolerance > 0.0f)
        printf("%ux%u, to %g\n", resolved.outer_iterations, resolved.inner_iterations,
               resolved.tolerance);
    else if (scene->solver.method == CVK_METHOD_EXPLICIT)
        printf("%s, kd %g\n", cvk_integrator_name(scene->solver.integrator ? scene->solver.integrator
                                                                          : CVK_INTEGRATOR_EULER),
               scene->solver.kd);
    else
        printf("%ux%u\n", resolved.outer_iterations, resolved.inner_iterations);
    printf("  residual %.4g m^2, max stretch %.3g %%, NaN %llu\n", st->residual,
           100.0 * st->max_stretch, (unsigned long long)st->nan_count);
    if (scene_tears(scene))
        printf("  torn springs %llu of %llu\n", (unsigned long long)st->torn_springs,
               (unsigned long long)(st->springs[0] + st->springs[1] + st->springs[2]));
    if (scene->solver.method == CVK_METHOD_IMPLICIT)
        printf("  %s: %u iterations in the last frame, %.2f per substep on average, %u "
               "breakdowns\n", cvk_linear_solver_name(scene->solver.linear),
               st->solver_iterations,
               (double)st->solver_iterations_total /
                   ((double)st->frames * scene->substeps + (st->frames == 0)),
               st->solver_breakdowns);
    else if (scene->solver.method == CVK_METHOD_PD)
        printf("  %s: %u sweeps in the last frame, %.2f per substep on average\n",
               cvk_linear_solver_name(scene->solver.linear), st->solver_iterations,
               (double)st->solver_iterations_total /
                   ((double)st->frames * scene->substeps + (st->frames == 0)));
    if (scene->collider_count > 0 || scene->collision.self)
        printf("  contacts: %llu with colliders, %llu between cloths; deepest penetration %.3g mm, "
               "%llu intersecting triangle pairs; %llu detections; %.3g %% of the particles' "
               "substeps held at a bound\n",
               (unsigned long long)st->collider_contacts, (unsigned long long)st->self_contacts,
               1e3 * st->max_penetration, (unsigned long long)st->intersecting_pairs,
               (unsigned long long)st->contact_searches, 100.0 * st->contact_held_fraction);
    if (t->frames == 0)
        return;
    printf("  %.3f ms per frame wall", t->wall_ms / t->frames);
    if (t->timed_frames) {
        printf(", %.3f ms %s (", t->gpu_ms / t->timed_frames,
               scene->solver.linear == CVK_LINEAR_GS_CPU ? "host" : "GPU");
        for (uint32_t p = 0; p < st->pass_count; p++)
            printf("%s%s %.3f", p ? ", " : "", st->passes[p].name, t->pass_ms[p] / t->timed_frames);
        printf(")");
    }
    printf(", %u dispatches per frame\n", st->dispatches_per_frame);
}

typedef struct dump_job {
    const float* xyz;
    uint64_t count;
} dump_job;

static bool write_dump(FILE* file, void* user)
{
    const dump_job* job = user;
    for (uint64_t p = 0; p < job->count; p++)
        if (fprintf(file, "%.9g,%.9g,%.9g\n", job->xyz[3 * p], job->xyz[3 * p + 1],
                    job->xyz[3 * p + 2]) < 0)
            return false;
    return true;
}

static int dump_positions(cvk_sim* sim, const char* path)
{
    uint64_t n = cvk_sim_particle_count(sim);
    float* xyz = malloc(3 * n * sizeof(float));
    if (!xyz) {
        app_error(tool, "out of memory for %llu positions", (unsigned long long)n);
        return APP_EXIT_FAILURE;
    }
    cvk_error err;
    if (cvk_sim_read_positions(sim, xyz, n, &err) != CVK_SUCCESS) {
        app_error(tool, "%s", err.message);
        free(xyz);
        return APP_EXIT_FAILURE;
    }
    dump_job job = {xyz, n};
    char message[512];
    bool ok = app_write_atomic(path, write_dump, &job, message, sizeof message);
    free(xyz);
    if (!ok) {
        app_error(tool, "%s", message);
        return APP_EXIT_FAILURE;
    }
    return APP_EXIT_OK;
}

static void print_obj_summary(const options* o, const app_obj_frames* out, uint32_t frames)
{
    /* A finished run wrote at least the start (frame 0, or a resume's first frame). */
    printf("  %u OBJ file%s in %s (frames 0 to %u of %u, every %u)\n", out->written,
           out->written == 1 ? "" : "s", o->obj, (out->written - 1) * o->every, frames, o->every);
}

/* --bake: a new cache; --resume: the simulation at the bake's last complete frame, and the
   frame count the bake's unless given. */
static int open_bake(const options* o, const cvk_scene* file, cvk_sim* sim, uint32_t* frames,
                     app_bake* bake)
{
    app_bake_desc desc = {o->scene, &o->overrides, cvk_scene_get_desc(file),
                          cvk_scene_get_json(file), *frames, o->every_given};
    if (o->bake)
        return app_bake_start(bake, tool, sim, o->bake, &desc);
    desc.frames = o->frames_set ? *frames : 0;
    int status = app_bake_resume(bake, tool, sim, o->resume, &desc);
    *frames = bake->frames;
    return status;
}

static void print_bake_summary(const app_bake* b)
{
    printf("  %u snapshots written in %s (the bake: frames 0 to %u of %u, every %u)\n",
           b->written, b->folder, app_bake_last_frame(b), b->frames, b->every);
}

/* Statistics after the frames, and the failure a non-finite coordinate makes. */
static int report(const options* o, const cvk_scene_desc* scene, const cvk_context* ctx,
                  cvk_sim* sim, uint32_t frames, const run_totals* totals,
                  const app_obj_frames* out, const app_bake* bake)
{
    cvk_sim_stats st;
    cvk_error err;
    if (cvk_sim_get_stats(sim, &st, &err) != CVK_SUCCESS) {
        app_error(tool, "%s", err.message);
        return APP_EXIT_FAILURE;
    }
    int written = APP_EXIT_OK;
    if (o->json || o->wedge_run)
        written = print_json(o, scene, ctx, sim, &st, totals);
    else
        print_summary(scene, ctx, &st, totals);
    if (o->wedge_run) {
        o->wedge_run->frames_done = totals->frames;
        o->wedge_run->frames = frames;
        o->wedge_run->diverged = st.diverged;
        o->wedge_run->diverged_frame = st.diverged_frame;
        o->wedge_run->timed_out = totals->timed_out;
    }
    if (written != APP_EXIT_OK)
        return written;
    if (o->obj && !o->json)
        print_obj_summary(o, out, frames);
    if (bake && !o->json && !o->wedge_run) /* a wedge prints one line at its end */
        print_bake_summary(bake);
    if (st.diverged) {
        app_error(tool, "%s: diverged in frame %llu, cloth %u: %s; stopped there", o->scene,
                  (unsigned long long)st.diverged_frame, st.diverged_cloth,
                  st.diverged_nonfinite ? "a position became NaN or infinite"
                                        : "a particle moved faster than 10000 m/s or a spring "
                                          "stretched past ten times its rest length");
        return APP_EXIT_DIVERGED;
    }
    if (st.nan_count) {
        app_error(tool, "%s: the simulation produced %llu non-finite coordinates", o->scene,
                  (unsigned long long)st.nan_count);
        return APP_EXIT_FAILURE;
    }
    if (totals->timed_out) {
        app_error(tool, "%s: passed its time limit of %u s after %u of %u frames; stopped there",
                  o->scene, o->wedge_run->time_limit_s, totals->frames, frames);
        return APP_EXIT_FAILURE;
    }
    return APP_EXIT_OK;
}

/* The frames (OBJ files, point cache), then statistics and the dump. Output folders are made
   once the scene has been built, so that bad input leaves nothing behind; the point cache is
   renamed into place only when the run succeeded. */
static int simulate(const options* o, const cvk_scene* file, const cvk_context* ctx,
                    cvk_sim* sim, uint32_t frames)
{
    const cvk_scene_desc* scene = cvk_scene_get_desc(file);
    app_bake bake = {0};
    bool baking = o->bake || o->resume;
    int status = baking ? open_bake(o, file, sim, &frames, &bake) : APP_EXIT_OK;
    app_obj_frames out = {0};
    app_pc2 pc2 = {0};
    if (status == APP_EXIT_OK && o->pc2)
        status = app_pc2_open(&pc2, tool, sim, o->pc2, scene, o->every);
    if (status == APP_EXIT_OK && o->obj && !app_obj_frames_init(&out, tool, sim, o->obj, scene))
        status = APP_EXIT_FAILURE;
    else if (status == APP_EXIT_OK && o->obj && !app_make_output_folder(tool, o->obj))
        status = APP_EXIT_BAD_INPUT;
    run_totals totals = {0};
    if (status == APP_EXIT_OK)
        status = run_frames(sim, frames, o->obj ? &out : NULL, o->pc2 ? &pc2 : NULL, o->every,
                            baking ? &bake : NULL, o->wedge_run ? o->wedge_run->deadline_ms : 0,
                            &totals);
    app_obj_frames_free(&out);
    app_bake done = bake; /* its counts, for the summary */
    app_bake_free(&bake);
    /* A wedge's preview: the last frame of a run that did not blow up (a timed-out one too). */
    bool preview = status == APP_EXIT_OK && o->wedge_run && o->wedge_run->preview_path &&
                   !totals.diverged;
    if (status == APP_EXIT_OK)
        status = report(o, scene, ctx, sim, frames, &totals, &out, baking ? &done : NULL);
    if (preview && (status == APP_EXIT_OK || totals.timed_out)) {
        int drawn = app_wedge_preview(tool, sim, scene, totals.frames, o->wedge_run->preview_path);
        status = status == APP_EXIT_OK ? drawn : status;
    }
    if (status == APP_EXIT_OK && o->pc2)
        status = app_pc2_finish(&pc2, frames, !o->json);
    app_pc2_free(&pc2);
    if (status == APP_EXIT_OK && o->dump)
        status = dump_positions(sim, o->dump);
    return status;
}

static int run(const options* o)
{
    cvk_scene* file = NULL;
    cvk_context* ctx = NULL;
    int status = app_open(tool, o->scene, &o->overrides, &file, &ctx);
    if (status != APP_EXIT_OK)
        return status;
    const cvk_scene_desc* scene = cvk_scene_get_desc(file);
    uint32_t frames = o->frames_set ? o->frames : scene->frames;
    cvk_error err;
    cvk_sim* sim = NULL;
    cvk_sim_desc sim_desc = cvk_default_sim_desc();
    sim_desc.scene = scene;
    sim_desc.workgroup_size = o->workgroup_size;
    sim_desc.max_workgroups = o->max_workgroups;
    sim_desc.search_lanes = o->search_lanes;
    cvk_result r = cvk_sim_create(ctx, &sim_desc, &sim, &err);
    if (r == CVK_SUCCESS && !o->json) /* --json lists them in its object */
        app_print_notes(tool, sim);
    if (r != CVK_SUCCESS) {
        app_error(tool, "%s: %s", o->scene, err.message);
        status = app_creation_status(r);
    } else if (o->plan) {
        size_t need = cvk_sim_describe_plan(sim, NULL, 0) + 1;
        char* text = malloc(need);
        if (text) {
            cvk_sim_describe_plan(sim, text, need);
            fputs(text, stdout);
            free(text);
        }
    } else {
        status = simulate(o, file, ctx, sim, frames);
    }
    cvk_sim_destroy(sim);
    return app_close(tool, ctx, file, status);
}

/* One variant of a wedge: the scene with its overrides, statistics into its folder. */
static int run_variant(void* user, const app_overrides* overrides, app_wedge_run* wedge_run)
{
    const options* base = user;
    options o = *base;
    o.overrides = *overrides;
    o.wedge_run = wedge_run;
    o.bake = wedge_run->bake_path;
    o.every = 1;
    return run(&o);
}

static int run_wedge(options* o)
{
    app_wedge w;
    int status = app_wedge_build(&w, tool, o->scene, &o->overrides, &o->wedge);
    if (status == APP_EXIT_OK && o->wedge.count)
        printf("%u\n", w.count);
    else if (status == APP_EXIT_OK && o->wedge.index_set)
        status = app_wedge_run_index(&w, &o->overrides, &o->wedge, o->wedge.index, run_variant, o);
    else if (status == APP_EXIT_OK)
        status = app_wedge_run_all(&w, &o->overrides, &o->wedge, run_variant, o);
    app_wedge_free(&w);
    return status;
}

/* clothvk-sim --wedge-gather DIR, alone on its command line. */
static bool gather_command(int argc, char** argv, int* status)
{
    for (int i = 1; i < argc; i++) {
        size_t length = 0;
        const char* value = app_option_split(argv[i], &length);
        if (length != strlen("--wedge-gather") || strncmp(argv[i], "--wedge-gather", length))
            continue;
        const char* folder = value ? value : i + 1 < argc ? argv[i + 1] : NULL;
        if (argc != (value ? 2 : 3)) {
            app_error(tool, "--wedge-gather DIR takes no other arguments");
            *status = APP_EXIT_BAD_INPUT;
        } else if (!folder || !folder[0]) {
            app_error(tool, "--wedge-gather: expected a wedge folder");
            *status = APP_EXIT_BAD_INPUT;
        } else {
            *status = app_wedge_gather(tool, folder);
        }
        return true;
    }
    return false;
}

int main(int argc, char** argv)
{
    int status = APP_EXIT_OK;
    if (gather_command(argc, argv, &status))
        return status;
    options o = {0};
    bool done = false;
    status = parse_args(argc, argv, &o, &done);
    if (status == APP_EXIT_OK && !done) {
        app_catch_interrupts();
        status = app_wedge_requested(&o.wedge) || o.wedge.out ? run_wedge(&o) : run(&o);
    }
    app_overrides_free(&o.overrides);
    app_wedge_options_free(&o.wedge);
    return status;
}
