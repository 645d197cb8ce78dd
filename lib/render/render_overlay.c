/* render.overlay: "frame N  t = X.XXX s" in the image's lower left corner, drawn on the host
   into the read-back pixels after the frame is complete. stb_easy_font builds the text from
   axis-aligned quads on a whole-number grid; each grid unit becomes a square of `scale`
   pixels, over a darkened box, so the bytes are the same on every device and run. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "render/render_internal.h"

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wmissing-braces"
#endif
#include <stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

enum {
    OVERLAY_MAX_QUADS = 600, /* stb_easy_font's quads for the text: about 10 a character */
    OVERLAY_PAD = 3,         /* font units of darkened box around the text */
};

/* One stb_easy_font vertex. */
typedef struct font_vertex {
    float x, y, z;
    unsigned char color[4];
} font_vertex;

/* Pixels [x0, x1) x [y0, y1), clipped to the image: darkened to `keep`/256 of their value, or
   set to white (keep < 0). */
static void fill(uint8_t* pixels, uint32_t width, uint32_t height, long x0, long y0, long x1, long y1, int keep)
{
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > (long)width ? (long)width : x1;
    y1 = y1 > (long)height ? (long)height : y1;
    for (long y = y0; y < y1; y++)
        for (long x = x0; x < x1; x++) {
            uint8_t* p = pixels + ((size_t)y * width + (size_t)x) * 4u;
            for (int c = 0; c < 3; c++)
                p[c] = keep < 0 ? 255 : (uint8_t)((p[c] * keep) >> 8);
            p[3] = 255;
        }
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void cvk_render_overlay_draw(cvk_renderer* rd)
{
    double start = now_ms();
    uint32_t width = rd->desc.size[0], height = rd->desc.size[1];
    double frame_time = (double)rd->mesh->sim->params.dt * rd->mesh->sim->params.substeps;
    double frame = frame_time > 0.0 ? floor(rd->seconds / frame_time + 0.5) : 0.0;
    char text[64];
    snprintf(text, sizeof text, "frame %.0f  t = %.3f s", frame, rd->seconds);
    font_vertex vertices[4 * OVERLAY_MAX_QUADS];
    int count = stb_easy_font_print(0.0f, 0.0f, text, NULL, vertices, (int)sizeof vertices);
    /* A grid unit is `scale` pixels: 2 at 720 rows, at least 1. */
    long scale = (long)height / 360 > 1 ? (long)height / 360 : 1;
    long text_w = 0, text_h = 0;
    for (int q = 0; q < count; q++) {
        text_w = text_w > lround(vertices[4 * q + 2].x) ? text_w : lround((vertices[4 * q + 2].x));
        text_h = text_h > lround(vertices[4 * q + 2].y) ? text_h : lround((vertices[4 * q + 2].y));
    }
    long left = 4 * scale, bottom = (long)height - 4 * scale;
    long box_x0 = left, box_y1 = bottom;
    long box_x1 = box_x0 + (text_w + 2 * OVERLAY_PAD) * scale, box_y0 = box_y1 - (text_h + 2 * OVERLAY_PAD) * scale;
    uint8_t* pixels = rd->readback.mapped;
    fill(pixels, width, height, box_x0, box_y0, box_x1, box_y1, 96);
    long ox = box_x0 + OVERLAY_PAD * scale, oy = box_y0 + OVERLAY_PAD * scale;
    for (int q = 0; q < count; q++) {
        const font_vertex* v = &vertices[4 * q];
        long x0 = lround(v[0].x), y0 = lround(v[0].y), x1 = lround(v[2].x), y1 = lround(v[2].y);
        fill(pixels, width, height, ox + x0 * scale, oy + y0 * scale, ox + x1 * scale, oy + y1 * scale, -1);
    }
    rd->overlay_ms = now_ms() - start;
}
