/* --wedge-gather DIR: one row per variant in DIR/wedges.csv and each variant's last frame in
   DIR/contact-sheet.png. A variant is read from what its folder holds: a variant that crashed,
   was killed or never started is a row that says so, never a missing one. */
#include "wedge.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_HDR
#define STBI_NO_LINEAR
#define STBI_FAILURE_USERMSG
/* stb's headers, as they are: warnings about their own code are not ours to fix. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wmissing-braces"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <stb_image.h>
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

/* Contact-sheet tiles: each last frame scaled to TILE_W pixels wide, its label below. */
#define TILE_W 256
#define PAD 6
#define LINE_H 11

/* One variant as its folder tells it. */
typedef struct row {
    json_t* values;   /* key -> value text */
    json_t* stats;    /* stats.json, or NULL */
    char state[32];   /* ok, diverged, timed-out, failed, crashed, cancelled, not-started, ... */
    char error[1024];
    json_int_t frames;         /* -1: unknown */
    json_int_t diverged_frame; /* -1: none */
} row;

/* The statistics columns, each a path into stats.json; the timing ones last. */
static const char* const stat_columns[][2] = {
    {"residual", "residual"},
    {"residual_normalized", "residual_normalized"},
    {"max_stretch", "max_stretch"},
    {"p99_stretch", "p99_stretch"},
    {"torn_springs", "torn_springs"},
    {"nan_count", "nan_count"},
    {"intersecting_pairs", "contacts.intersecting_pairs"},
    {"max_penetration", "contacts.max_penetration"},
    {"iterations_per_substep", "linear_solver.iterations_per_substep"},
    {"wall_ms_per_frame", "wall_ms_per_frame"},
    {"gpu_ms_per_frame", "gpu_ms_per_frame"},
};

static char* join(const char* folder, const char* name)
{
    size_t len = strlen(folder) + strlen(name) + 2;
    char* path = malloc(len);
    if (path)
        snprintf(path, len, "%s/%s", folder, name);
    return path;
}

static json_t* load_json(const char* folder, const char* name)
{
    char* path = join(folder, name);
    json_t* root = path ? json_load_file(path, 0, NULL) : NULL;
    free(path);
    return root;
}

/* The last non-empty line of a variant's log, or "". */
static void last_log_line(const char* folder, char* out, size_t size)
{
    out[0] = '\0';
    char* path = join(folder, "log.txt");
    FILE* f = path ? fopen(path, "r") : NULL;
    char line[1024];
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        if (line[0])
            snprintf(out, size, "%s", line);
    }
    if (f)
        fclose(f);
    free(path);
}

/* DIR/states.tsv: "K<TAB>STATE<TAB>DETAIL" lines into an object "K" -> [STATE, DETAIL]. */
static json_t* load_states(const char* folder)
{
    json_t* states = json_object();
    char* path = join(folder, "states.tsv");
    FILE* f = path ? fopen(path, "r") : NULL;
    char line[1024];
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char* state = strchr(line, '\t');
        if (!state)
            continue;
        *state++ = '\0';
        char* detail = strchr(state, '\t');
        if (detail)
            *detail++ = '\0';
        json_object_set_new(states, line, json_pack("[ss]", state, detail ? detail : ""));
    }
    if (f)
        fclose(f);
    free(path);
    return states;
}

/* A variant whose status never reached its end: what the scheduler (or --jobs) said, if known. */
static void unfinished(row* r, const json_t* state, bool started, const char* log_line)
{
    const char* s = json_string_value(json_array_get(state, 0));
    const char* detail = json_string_value(json_array_get(state, 1));
    const char* kind = !s                                        ? "crashed"
                       : !strcmp(s, "TIMEOUT") || !strcmp(s, "KILLED") ? "timed-out"
                       : !strcmp(s, "CANCELLED")                 ? "cancelled"
                       : !strcmp(s, "OUT_OF_MEMORY")             ? "out-of-memory"
                       : !strcmp(s, "PENDING") || !strcmp(s, "RUNNING") ? "unfinished"
                                                                 : "crashed";
    snprintf(r->state, sizeof r->state, "%s", started || s ? kind : "not-started");
    char why[512];
    if (s)
        snprintf(why, sizeof why, "%s%s%s", s, detail && detail[0] ? ": " : "",
                 detail ? detail : "");
    else
        snprintf(why, sizeof why, "%s", started ? "no end status (status.json still says running): "
                 "crashed or killed" : "no status.json: the variant never started");
    snprintf(r->error, sizeof r->error, "%s%s%s", why, log_line[0] ? "; its log ends: " : "",
             log_line);
}

static void read_row(row* r, const char* out, uint32_t index, const json_t* states)
{
    char name[32];
    snprintf(name, sizeof name, "v%04u", index);
    char* folder = join(out, name);
    json_t* status = folder ? load_json(folder, "status.json") : NULL;
    r->stats = folder ? load_json(folder, "stats.json") : NULL;
    r->frames = -1;
    r->diverged_frame = -1;
    const char* state = json_string_value(json_object_get(status, "state"));
    snprintf(name, sizeof name, "%u", index);
    char log_line[1024] = "";
    if (folder)
        last_log_line(folder, log_line, sizeof log_line);
    if (!state || !strcmp(state, "running")) {
        unfinished(r, json_object_get(states, name), state != NULL, log_line);
    } else {
        snprintf(r->state, sizeof r->state, "%s", state);
        const char* error = json_string_value(json_object_get(status, "error"));
        snprintf(r->error, sizeof r->error, "%s", error ? error : "");
        r->frames = json_integer_value(json_object_get(status, "frames"));
        json_t* at = json_object_get(status, "diverged_frame");
        r->diverged_frame = at ? json_integer_value(at) : -1;
    }
    json_decref(status);
    free(folder);
}

/* ---- the table ---------------------------------------------------------------------------- */

static void put_csv(FILE* f, const char* text)
{
    if (!strpbrk(text, ",\"\n\r")) {
        fputs(text, f);
        return;
    }
    fputc('"', f);
    for (const char* c = text; *c; c++) {
        if (*c == '"')
            fputc('"', f);
        fputc(*c, f);
    }
    fputc('"', f);
}

/* A varied value as written, a string without its JSON quotes, into out. */
static void value_display(const char* text, char* out, size_t size)
{
    json_t* parsed = text ? json_loads(text, JSON_DECODE_ANY, NULL) : NULL;
    snprintf(out, size, "%s", json_is_string(parsed) ? json_string_value(parsed) : text ? text : "");
    json_decref(parsed);
}

static void put_value(FILE* f, const char* text)
{
    char shown[1024];
    value_display(text, shown, sizeof shown);
    put_csv(f, shown);
}

static const json_t* stat_value(const json_t* stats, const char* path)
{
    const char* dot = strchr(path, '.');
    if (!dot)
        return json_object_get(stats, path);
    char head[64];
    snprintf(head, sizeof head, "%.*s", (int)(dot - path), path);
    return json_object_get(json_object_get(stats, head), dot + 1);
}

static void put_number(FILE* f, const json_t* v)
{
    if (json_is_integer(v))
        fprintf(f, "%lld", (long long)json_integer_value(v));
    else if (json_is_real(v))
        fprintf(f, "%.9g", json_real_value(v));
}

typedef struct table {
    const json_t* keys;
    const row* rows;
    uint32_t count;
} table;

static bool write_table(FILE* f, void* user)
{
    const table* t = user;
    size_t k;
    json_t* key;
    fputs("variant", f);
    json_array_foreach(t->keys, k, key) {
        fputc(',', f);
        put_csv(f, json_string_value(key));
    }
    fputs(",status,frames_run,diverged,diverged_frame", f);
    for (size_t c = 0; c < sizeof stat_columns / sizeof stat_columns[0]; c++)
        fprintf(f, ",%s", stat_columns[c][0]);
    fputs(",error\n", f);
    for (uint32_t i = 0; i < t->count; i++) {
        const row* r = &t->rows[i];
        fprintf(f, "%u", i);
        json_array_foreach(t->keys, k, key) {
            fputc(',', f);
            put_value(f, json_string_value(json_object_get(r->values, json_string_value(key))));
        }
        fprintf(f, ",%s,", r->state);
        if (r->frames >= 0)
            fprintf(f, "%lld", (long long)r->frames);
        fprintf(f, ",%s,", !strcmp(r->state, "diverged") ? "true" : r->stats ? "false" : "");
        if (r->diverged_frame >= 0)
            fprintf(f, "%lld", (long long)r->diverged_frame);
        for (size_t c = 0; c < sizeof stat_columns / sizeof stat_columns[0]; c++) {
            fputc(',', f);
            put_number(f, stat_value(r->stats, stat_columns[c][1]));
        }
        fputc(',', f);
        put_csv(f, r->error);
        fputc('\n', f);
    }
    return !ferror(f);
}

/* ---- the contact sheet -------------------------------------------------------------------- */

typedef struct sheet {
    uint8_t* pixels;
    uint32_t width, height;
    char* vertices; /* stb_easy_font's quads for one line */
} sheet;

#define LINE_CHARS 256
#define VERTEX_BYTES (LINE_CHARS * 270) /* stb's estimate per character */

static void fill(sheet* s, int x0, int y0, int x1, int y1, const uint8_t rgb[3])
{
    for (int y = y0 < 0 ? 0 : y0; y < y1 && y < (int)s->height; y++)
        for (int x = x0 < 0 ? 0 : x0; x < x1 && x < (int)s->width; x++) {
            uint8_t* p = s->pixels + 4 * ((size_t)y * s->width + (size_t)x);
            p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2], p[3] = 255;
        }
}

/* One line of text at (x, y), cut to `max_w` pixels: stb_easy_font's quads, each an
   axis-aligned rectangle of whole pixels. */
static void text(sheet* s, int x, int y, const char* line, int max_w, const uint8_t rgb[3])
{
    char cut[LINE_CHARS];
    snprintf(cut, sizeof cut, "%s", line);
    for (size_t n = strlen(cut); n > 0 && stb_easy_font_width(cut) > max_w; n--)
        cut[n - 1] = '\0';
    char* vertices = s->vertices;
    int quads = stb_easy_font_print((float)x, (float)y, cut, NULL, vertices, VERTEX_BYTES);
    for (int q = 0; q < quads; q++) {
        float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
        for (int v = 0; v < 4; v++) {
            float xy[2];
            memcpy(xy, vertices + (size_t)(4 * q + v) * 16, sizeof xy);
            for (int a = 0; a < 2; a++) {
                lo[a] = fminf(lo[a], xy[a]);
                hi[a] = fmaxf(hi[a], xy[a]);
            }
        }
        fill(s, (int)lroundf(lo[0]), (int)lroundf(lo[1]), (int)lroundf(hi[0]), (int)lroundf(hi[1]),
             rgb);
    }
}

/* `image` (w x h RGBA) scaled by area averaging into the tile at (x, y), tw x th. */
static void place(sheet* s, const uint8_t* image, int w, int h, int x, int y, int tw, int th)
{
    for (int ty = 0; ty < th; ty++) {
        int y0 = ty * h / th, y1 = (ty + 1) * h / th;
        y1 = y1 > y0 ? y1 : y0 + 1;
        for (int tx = 0; tx < tw; tx++) {
            int x0 = tx * w / tw, x1 = (tx + 1) * w / tw;
            x1 = x1 > x0 ? x1 : x0 + 1;
            unsigned sum[3] = {0, 0, 0}, n = 0;
            for (int sy = y0; sy < y1 && sy < h; sy++)
                for (int sx = x0; sx < x1 && sx < w; sx++, n++)
                    for (int c = 0; c < 3; c++)
                        sum[c] += image[4 * ((size_t)sy * (size_t)w + (size_t)sx) + (size_t)c];
            uint8_t rgb[3] = {(uint8_t)(sum[0] / (n ? n : 1)), (uint8_t)(sum[1] / (n ? n : 1)),
                              (uint8_t)(sum[2] / (n ? n : 1))};
            fill(s, x + tx, y + ty, x + tx + 1, y + ty + 1, rgb);
        }
    }
}

/* Each variant's last.png; the tile height from the first image's shape. */
static uint8_t** load_images(const char* out, uint32_t count, int* w, int* h, int* tile_h)
{
    uint8_t** images = calloc(count ? count : 1, sizeof *images);
    *tile_h = TILE_W * 9 / 16;
    for (uint32_t i = 0; images && i < count; i++) {
        char name[32];
        snprintf(name, sizeof name, "v%04u/last.png", i);
        char* path = join(out, name);
        int channels;
        images[i] = path ? stbi_load(path, &w[i], &h[i], &channels, 4) : NULL;
        free(path);
        if (images[i] && *tile_h == TILE_W * 9 / 16 && w[i] > 0)
            *tile_h = (int)((long)TILE_W * h[i] / w[i]);
    }
    if (*tile_h < 16)
        *tile_h = 16;
    if (*tile_h > 4 * TILE_W)
        *tile_h = 4 * TILE_W;
    return images;
}

static int write_sheet(const char* tool, const char* out, const json_t* keys, const row* rows,
                       uint32_t count)
{
    int* w = calloc(count ? count : 1, sizeof *w);
    int* h = calloc(count ? count : 1, sizeof *h);
    int tile_h = 0;
    uint8_t** images = w && h ? load_images(out, count, w, h, &tile_h) : NULL;
    uint32_t columns = (uint32_t)ceil(sqrt((double)count));
    columns = columns ? columns : 1;
    uint32_t lines = (uint32_t)json_array_size(keys) + 1;
    int cell_w = TILE_W + 2 * PAD, cell_h = tile_h + (int)lines * LINE_H + 3 * PAD;
    sheet s = {NULL, columns * (uint32_t)cell_w, ((count + columns - 1) / columns) * (uint32_t)cell_h,
               malloc(VERTEX_BYTES)};
    s.pixels = images && s.vertices ? malloc((size_t)s.width * s.height * 4 + 4) : NULL;
    int status = APP_EXIT_OK;
    if (!s.pixels) {
        app_error(tool, "out of memory for the contact sheet");
        status = APP_EXIT_FAILURE;
    }
    const uint8_t background[3] = {24, 24, 28}, empty[3] = {60, 60, 66}, label[3] = {230, 230, 230},
                  good[3] = {120, 220, 120}, bad[3] = {255, 140, 90};
    if (s.pixels)
        fill(&s, 0, 0, (int)s.width, (int)s.height, background);
    for (uint32_t i = 0; s.pixels && i < count; i++) {
        int x = (int)(i % columns) * cell_w + PAD, y = (int)(i / columns) * cell_h + PAD;
        if (images[i]) {
            int th = (int)((long)TILE_W * h[i] / w[i]);
            place(&s, images[i], w[i], h[i], x, y, TILE_W, th < tile_h ? th : tile_h);
        } else {
            fill(&s, x, y, x + TILE_W, y + tile_h, empty);
        }
        int ty = y + tile_h + PAD;
        char line[300];
        size_t k;
        json_t* key;
        json_array_foreach(keys, k, key) {
            const char* v = json_string_value(json_object_get(rows[i].values,
                                                              json_string_value(key)));
            char shown[256];
            value_display(v, shown, sizeof shown);
            snprintf(line, sizeof line, "%s=%s", json_string_value(key), v ? shown : "(scene's)");
            text(&s, x, ty, line, TILE_W, label);
            ty += LINE_H;
        }
        if (rows[i].diverged_frame >= 0)
            snprintf(line, sizeof line, "v%04u %s at frame %lld", i, rows[i].state,
                     (long long)rows[i].diverged_frame);
        else if (!strcmp(rows[i].state, "timed-out") && rows[i].frames >= 0)
            snprintf(line, sizeof line, "v%04u %s after %lld frames", i, rows[i].state,
                     (long long)rows[i].frames);
        else
            snprintf(line, sizeof line, "v%04u %s", i, rows[i].state);
        text(&s, x, ty, line, TILE_W, strcmp(rows[i].state, "ok") ? bad : good);
    }
    if (s.pixels) {
        char* path = join(out, "contact-sheet.png");
        cvk_image image = {s.pixels, s.width, s.height, s.width * 4};
        cvk_error err;
        if (!path || cvk_image_write_png(&image, path, &err) != CVK_SUCCESS) {
            app_error(tool, "%s", path ? err.message : "out of memory");
            status = APP_EXIT_FAILURE;
        }
        free(path);
    }
    for (uint32_t i = 0; images && i < count; i++)
        stbi_image_free(images[i]);
    free(images);
    free(s.pixels);
    free(s.vertices);
    free(w);
    free(h);
    return status;
}

/* ---- the gather --------------------------------------------------------------------------- */

static json_t* load_manifest(const char* tool, const char* out)
{
    char* path = join(out, "wedge.json");
    json_error_t jerr;
    json_t* m = path ? json_load_file(path, 0, &jerr) : NULL;
    if (!m)
        app_error(tool, "%s: %s (the wedge's manifest; a run with --wedge-index or --jobs "
                  "writes it)", path ? path : out, jerr.text);
    else if (strcmp(json_string_value(json_object_get(m, "format")) ?
                        json_string_value(json_object_get(m, "format")) : "", APP_WEDGE_FORMAT) ||
             !json_is_array(json_object_get(m, "variants")) ||
             !json_is_array(json_object_get(m, "keys"))) {
        app_error(tool, "%s: not a wedge manifest (no \"format\": \"%s\" with keys and "
                  "variants)", path, APP_WEDGE_FORMAT);
        json_decref(m);
        m = NULL;
    }
    free(path);
    return m;
}

int app_wedge_gather(const char* tool, const char* out)
{
    json_t* manifest = load_manifest(tool, out);
    if (!manifest)
        return APP_EXIT_BAD_INPUT;
    const json_t* keys = json_object_get(manifest, "keys");
    const json_t* variants = json_object_get(manifest, "variants");
    uint32_t count = (uint32_t)json_array_size(variants);
    row* rows = calloc(count ? count : 1, sizeof *rows);
    json_t* states = load_states(out);
    int status = rows ? APP_EXIT_OK : APP_EXIT_FAILURE;
    uint32_t ok = 0;
    for (uint32_t i = 0; rows && i < count; i++) {
        rows[i].values = json_array_get(variants, i);
        read_row(&rows[i], out, i, states);
        ok += !strcmp(rows[i].state, "ok");
    }
    char* path = join(out, "wedges.csv");
    table t = {keys, rows, count};
    char message[600];
    if (status == APP_EXIT_OK && (!path || !app_write_atomic(path, write_table, &t, message,
                                                             sizeof message))) {
        app_error(tool, "%s", path ? message : "out of memory");
        status = APP_EXIT_FAILURE;
    }
    if (status == APP_EXIT_OK)
        status = write_sheet(tool, out, keys, rows, count);
    if (status == APP_EXIT_OK)
        printf("%s: %u variant%s, %u ok, %u not: %s/wedges.csv, %s/contact-sheet.png\n", tool,
               count, count == 1 ? "" : "s", ok, count - ok, out, out);
    for (uint32_t i = 0; rows && i < count; i++)
        json_decref(rows[i].stats);
    free(rows);
    free(path);
    json_decref(states);
    json_decref(manifest);
    return status;
}
