#include "render/camera.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* How far past its rest distance from a pin a hanging cloth is assumed to stretch: hanging.json
   (seed 002's 4 x 4 iterations, 160 to 200 % stretch at the pins) hangs 1.30 times its rest
   distance below them. */
#define REACH_STRETCH 1.35

/* Pins a particle is checked against: any subset gives a box that still holds it. */
#define REACH_MAX_PINS 64u

#define PI 3.14159265358979323846

/* ---- small vector helpers ---- */

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double out[3])
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, c, sizeof c);
}

static void normalize(double v[3])
{
    double len = sqrt(dot(v, v));
    if (len > 0)
        for (int k = 0; k < 3; k++)
            v[k] /= len;
}

static void to_double(const float in[3], double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = in[k];
}

void cvk_box_empty(cvk_box* b)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = INFINITY;
        b->hi[k] = -INFINITY;
    }
}

void cvk_box_add(cvk_box* b, const double p[3])
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = fmin(b->lo[k], p[k]);
        b->hi[k] = fmax(b->hi[k], p[k]);
    }
}

static void box_corner(const cvk_box* b, int corner, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (corner >> k) & 1 ? b->hi[k] : b->lo[k];
}

/* ---- the reach ---- */

/* Grows `box` by where the free particles of one cloth can hang from its pins. */
static void add_hanging(const cvk_build* b, const cvk_cloth_range* c, const double gravity[3], cvk_box* box)
{
    uint32_t n = c->particle_count;
    uint32_t pins = 0;
    for (uint32_t i = 0; i < n; i++)
        pins += b->internal_of[c->first_user + i] >= b->free_count;
    if (pins == 0)
        return;
    uint32_t step = (pins + REACH_MAX_PINS - 1) / REACH_MAX_PINS;
    double scale = REACH_STRETCH * (c->rest_scale > 1.0f ? c->rest_scale : 1.0);
    /* Falling along one axis: a cloth does not climb above where it starts. */
    int fall_axis = -1;
    double g = sqrt(dot(gravity, gravity));
    for (int k = 0; k < 3; k++)
        if (fabs(gravity[k]) > 0.999 * g)
            fall_axis = k;
    double start_lo = INFINITY, start_hi = -INFINITY;
    for (uint32_t i = 0; fall_axis >= 0 && i < n; i++) {
        const float* x = &b->position[3 * (size_t)b->internal_of[c->first_user + i]];
        start_lo = fmin(start_lo, x[fall_axis]);
        start_hi = fmax(start_hi, x[fall_axis]);
    }
    for (uint32_t i = 0; i < n; i++) {
        uint32_t p = b->internal_of[c->first_user + i];
        if (p >= b->free_count)
            continue;
        const float* x = &b->position[3 * (size_t)p];
        double lo[3] = {-INFINITY, -INFINITY, -INFINITY}, hi[3] = {INFINITY, INFINITY, INFINITY};
        uint32_t seen = 0;
        for (uint32_t j = 0; j < n; j++) {
            uint32_t q = b->internal_of[c->first_user + j];
            if (q < b->free_count || seen++ % step != 0)
                continue;
            const float* pin = &b->position[3 * (size_t)q];
            double d[3] = {x[0] - pin[0], x[1] - pin[1], x[2] - pin[2]};
            double r = scale * sqrt(dot(d, d));
            for (int k = 0; k < 3; k++) {
                lo[k] = fmax(lo[k], pin[k] - r);
                hi[k] = fmin(hi[k], pin[k] + r);
            }
        }
        if (fall_axis >= 0 && gravity[fall_axis] < 0)
            hi[fall_axis] = fmin(hi[fall_axis], start_hi);
        if (fall_axis >= 0 && gravity[fall_axis] > 0)
            lo[fall_axis] = fmax(lo[fall_axis], start_lo);
        cvk_box_add(box, lo);
        cvk_box_add(box, hi);
    }
}

void cvk_reach_box(const cvk_build* b, const double gravity[3], cvk_box* out)
{
    cvk_box_empty(out);
    for (uint32_t p = 0; p < b->particle_count; p++) {
        double x[3];
        to_double(&b->position[3 * (size_t)p], x);
        cvk_box_add(out, x);
    }
    if (dot(gravity, gravity) == 0.0)
        return;
    for (uint32_t c = 0; c < b->cloth_count; c++)
        add_hanging(b, &b->cloths[c], gravity, out);
}

/* The colliders near the cloths: each collider box that overlaps the cloths' reach grown by
   its own size on every side, clipped to that grown box. */
static void add_colliders(const cvk_view_colliders* c, cvk_box* reach)
{
    double size = 1e-3;
    for (int k = 0; k < 3; k++)
        size = fmax(size, reach->hi[k] - reach->lo[k]);
    cvk_box near;
    for (int k = 0; k < 3; k++) {
        near.lo[k] = reach->lo[k] - size;
        near.hi[k] = reach->hi[k] + size;
    }
    for (uint32_t i = 0; i < c->box_count; i++) {
        const cvk_box* b = &c->boxes[i];
        double lo[3], hi[3];
        bool overlaps = true;
        for (int k = 0; k < 3; k++) {
            lo[k] = fmax(b->lo[k], near.lo[k]);
            hi[k] = fmin(b->hi[k], near.hi[k]);
            overlaps = overlaps && lo[k] <= hi[k];
        }
        if (!overlaps)
            continue;
        cvk_box_add(reach, lo);
        cvk_box_add(reach, hi);
    }
}

/* ---- matrices: column-major, m[column * 4 + row] ---- */

static void multiply(const double a[16], const double b[16], double out[16])
{
    double m[16];
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + r] * b[c * 4 + k];
            m[c * 4 + r] = s;
        }
    memcpy(out, m, sizeof m);
}

/* Rows of an affine map: clip = rows · (p, 1). */
static void from_rows(double rows[4][4], double out[16])
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            out[c * 4 + r] = rows[r][c];
}

static void to_float(const double in[16], float out[16])
{
    for (int i = 0; i < 16; i++)
        out[i] = (float)in[i];
}

/* Right, up and back (towards the eye) of a camera at eye looking at target. */
static void camera_basis(const double eye[3], const double target[3], const double up[3], double right[3],
                         double cam_up[3], double back[3])
{
    for (int k = 0; k < 3; k++)
        back[k] = eye[k] - target[k];
    normalize(back);
    cross(up, back, right);
    /* Looking straight along up (an automatic target below a given eye): any sideways will do. */
    if (dot(right, right) < 1e-12) {
        double other[3] = {fabs(back[0]) < 0.9 ? 1.0 : 0.0, fabs(back[0]) < 0.9 ? 0.0 : 1.0, 0.0};
        cross(other, back, right);
    }
    normalize(right);
    cross(back, right, cam_up);
}

/* ---- placing the camera ---- */

/* The default view: from the front (+z, or +x when up is along z), to the right and above. */
static void default_view_direction(const double up[3], double out[3])
{
    double front[3] = {0.0, 0.0, 1.0};
    if (fabs(up[2]) > 0.9) {
        front[0] = 1.0;
        front[2] = 0.0;
    }
    double along = dot(front, up);
    for (int k = 0; k < 3; k++)
        front[k] -= along * up[k];
    normalize(front);
    double right[3];
    cross(up, front, right);
    for (int k = 0; k < 3; k++)
        out[k] = 0.55 * right[k] + 0.42 * up[k] + 1.0 * front[k];
    normalize(out);
}

/* The points the view must hold: the reach's corners. */
static int framing_points(const cvk_view* v, double points[8][3])
{
    for (int c = 0; c < 8; c++)
        box_corner(&v->reach, c, points[c]);
    return 8;
}

/* Distance from target along `back` at which every point fits in the field of view. */
static double fit_distance(const cvk_view* v, const double back[3], double points[][3], int count)
{
    double eye[3];
    for (int k = 0; k < 3; k++)
        eye[k] = v->target[k] + back[k];
    double right[3], cam_up[3], b[3];
    camera_basis(eye, v->target, v->up, right, cam_up, b);
    /* 6 % of the frame stays free at the edges. */
    double ty = tan(v->fov_y * PI / 360.0) * 0.94, tx = ty * v->aspect;
    double distance = 0.0;
    for (int i = 0; i < count; i++) {
        double o[3] = {points[i][0] - v->target[0], points[i][1] - v->target[1], points[i][2] - v->target[2]};
        double x = fabs(dot(o, right)), y = fabs(dot(o, cam_up)), z = dot(o, b);
        distance = fmax(distance, fmax(z + x / tx, z + y / ty));
    }
    return distance;
}

/* render.fit: the camera along `back` from the middle of the points' picture, as near as keeps
   `margin` of the image free on each side. The points are projected and the target moved
   sideways to centre them, twice (a perspective picture is not centred on the points' box's
   centre). */
static void fit_camera(const cvk_render_desc* desc, const cvk_view_fit* fit, cvk_view* v)
{
    const double(*points)[3] = (const double(*)[3])fit->xyz;
    uint64_t count = fit->count;
    double back[3];
    if (desc->auto_eye) {
        default_view_direction(v->up, back);
    } else {
        for (int k = 0; k < 3; k++)
            back[k] = (double)desc->eye[k] - desc->target[k];
        normalize(back);
    }
    for (int k = 0; k < 3; k++)
        v->target[k] = 0.5 * (v->reach.lo[k] + v->reach.hi[k]);
    double size = 1e-3;
    for (int k = 0; k < 3; k++)
        size = fmax(size, v->reach.hi[k] - v->reach.lo[k]);
    double share = 1.0 - 2.0 * desc->fit_margin;
    double ty = tan(v->fov_y * PI / 360.0), tx = ty * v->aspect;
    double distance = 0.0;
    for (int pass = 0; pass < 3; pass++) {
        double eye[3];
        for (int k = 0; k < 3; k++)
            eye[k] = v->target[k] + back[k];
        double right[3], cam_up[3], b[3];
        camera_basis(eye, v->target, v->up, right, cam_up, b);
        /* Nearest distance at which every corner lies within the share of the frame. */
        distance = 0.0;
        for (uint64_t i = 0; i < count; i++) {
            double o[3] = {points[i][0] - v->target[0], points[i][1] - v->target[1], points[i][2] - v->target[2]};
            double x = fabs(dot(o, right)), y = fabs(dot(o, cam_up)), z = dot(o, b);
            distance = fmax(distance, fmax(z + x / (share * tx), z + y / (share * ty)));
        }
        distance = fmax(distance, 0.5 * size + 1e-3);
        if (pass == 2)
            break;
        /* The corners' picture from there, and the target moved to its middle. */
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (uint64_t i = 0; i < count; i++) {
            double o[3];
            for (int k = 0; k < 3; k++)
                o[k] = points[i][k] - v->target[k] - distance * back[k];
            double depth = -dot(o, b);
            double sx = dot(o, right) / depth, sy = dot(o, cam_up) / depth;
            lo[0] = fmin(lo[0], sx), hi[0] = fmax(hi[0], sx);
            lo[1] = fmin(lo[1], sy), hi[1] = fmax(hi[1], sy);
        }
        double cx = 0.5 * (lo[0] + hi[0]) * distance, cy = 0.5 * (lo[1] + hi[1]) * distance;
        for (int k = 0; k < 3; k++)
            v->target[k] += cx * right[k] + cy * cam_up[k];
    }
    for (int k = 0; k < 3; k++)
        v->eye[k] = v->target[k] + distance * back[k];
}

static void place_camera(const cvk_render_desc* desc, cvk_view* v)
{
    double points[8][3];
    int count = framing_points(v, points);
    if (desc->auto_target) {
        cvk_box all;
        cvk_box_empty(&all);
        for (int i = 0; i < count; i++)
            cvk_box_add(&all, points[i]);
        for (int k = 0; k < 3; k++)
            v->target[k] = 0.5 * (all.lo[k] + all.hi[k]);
    } else {
        to_double(desc->target, v->target);
    }
    if (!desc->auto_eye) {
        to_double(desc->eye, v->eye);
        return;
    }
    double back[3];
    default_view_direction(v->up, back);
    double distance = fit_distance(v, back, points, count);
    double size = 0.0;
    for (int k = 0; k < 3; k++)
        size = fmax(size, v->reach.hi[k] - v->reach.lo[k]);
    distance = fmax(distance, 0.5 * size + 1e-3);
    for (int k = 0; k < 3; k++)
        v->eye[k] = v->target[k] + distance * back[k];
}

static void camera_matrix(cvk_view* v)
{
    double right[3], cam_up[3], back[3];
    camera_basis(v->eye, v->target, v->up, right, cam_up, back);
    double view[4][4] = {
        {right[0], right[1], right[2], -dot(right, v->eye)},
        {cam_up[0], cam_up[1], cam_up[2], -dot(cam_up, v->eye)},
        {back[0], back[1], back[2], -dot(back, v->eye)},
        {0, 0, 0, 1},
    };
    /* Vulkan clip space: y down, depth in [0, 1]; reversed (1 at near) so a float depth
       buffer keeps its precision far away. */
    double f = 1.0 / tan(v->fov_y * PI / 360.0);
    double n = v->near, fr = v->far;
    double projection[4][4] = {
        {f / v->aspect, 0, 0, 0},
        {0, -f, 0, 0},
        {0, 0, n / (fr - n), n * fr / (fr - n)},
        {0, 0, -1, 0},
    };
    double a[16], b[16], m[16];
    from_rows(projection, a);
    from_rows(view, b);
    multiply(a, b, m);
    to_float(m, v->view_proj);

    /* Pixel rays, for the ground: forward + x tan(fov_x / 2) right − y tan(fov_y / 2) up. */
    double ty = 1.0 / f, tx = ty * v->aspect;
    for (int k = 0; k < 3; k++) {
        v->ray_base[k] = -back[k] - tx * right[k] + ty * cam_up[k];
        v->ray_dx[k] = 2.0 * tx * right[k] / v->width;
        v->ray_dy[k] = -2.0 * ty * cam_up[k] / v->height;
    }
}

static void depth_range(cvk_view* v, const cvk_view_colliders* colliders)
{
    double right[3], cam_up[3], back[3];
    camera_basis(v->eye, v->target, v->up, right, cam_up, back);
    double nearest = INFINITY, farthest = 0.0;
    for (int c = 0; c < 8; c++) {
        double p[3];
        box_corner(&v->reach, c, p);
        double o[3] = {p[0] - v->eye[0], p[1] - v->eye[1], p[2] - v->eye[2]};
        double d = -dot(o, back);
        nearest = fmin(nearest, d);
        farthest = fmax(farthest, d);
    }
    /* Colliders drawn beyond the reach (a plane's square, a far box) stay inside the planes; one
       reaching behind the eye leaves the near plane at its floor below. */
    for (int c = 0; colliders && colliders->drawn.lo[0] <= colliders->drawn.hi[0] && c < 8; c++) {
        double p[3];
        box_corner(&colliders->drawn, c, p);
        double o[3] = {p[0] - v->eye[0], p[1] - v->eye[1], p[2] - v->eye[2]};
        double d = -dot(o, back);
        nearest = fmin(nearest, d);
        farthest = fmax(farthest, d);
    }
    double to_target = sqrt((v->eye[0] - v->target[0]) * (v->eye[0] - v->target[0]) +
                            (v->eye[1] - v->target[1]) * (v->eye[1] - v->target[1]) +
                            (v->eye[2] - v->target[2]) * (v->eye[2] - v->target[2]));
    /* The ground is drawn per pixel from its plane, not rasterised: only the reach needs to
       fit between the planes. */
    v->far = 1.5 * fmax(farthest, to_target) + 1e-3;
    v->near = fmax(0.5 * nearest, 1e-4 * v->far);
    v->fog_start = 1.5 * to_target;
    v->fog_end = 5.0 * to_target;
}

/* ---- the key light's shadow frustum: orthographic, fitted to the reach ---- */

/* spread: the tangent of half the key light's angular size with soft shadows, else 0; the map
   reaches that much further per metre of depth, so the penumbra around a shadow's edge lies
   inside it (and inside the patch of ground that reads it). */
static void light_matrix(cvk_view* v, uint32_t shadow_map_size, double spread)
{
    const double* l = v->key_direction;
    double reference[3] = {v->up[0], v->up[1], v->up[2]};
    if (fabs(dot(l, reference)) > 0.99) {
        reference[0] = 1.0;
        reference[1] = reference[2] = 0.0;
        if (fabs(l[0]) > 0.99) {
            reference[0] = 0.0;
            reference[1] = 1.0;
        }
    }
    double right[3], up[3];
    cross(reference, l, right);
    normalize(right);
    cross(l, right, up);
    cvk_box box;
    cvk_box_empty(&box);
    for (int c = 0; c < 8; c++) {
        double p[3];
        box_corner(&v->reach, c, p);
        double q[3] = {dot(p, right), dot(p, up), dot(p, l)};
        cvk_box_add(&box, q);
        /* Soft shadows need the distance from what casts a shadow to the ground it falls on:
           the depths reach down to the ground under each corner. */
        double above = dot(p, v->up) - v->ground_height, elevation = dot(l, v->up);
        if (spread > 0.0 && above > 0.0 && elevation > 0.02)
            box.lo[2] = fmin(box.lo[2], q[2] - above / elevation);
    }
    /* Square texels; a few texels of margin so PCF near the edge reads real depth. */
    double half = 0.5 * fmax(box.hi[0] - box.lo[0], box.hi[1] - box.lo[1]) + spread * (box.hi[2] - box.lo[2]);
    half *= 1.0 + 8.0 / shadow_map_size;
    half = fmax(half, 1e-4);
    double cx = 0.5 * (box.lo[0] + box.hi[0]), cy = 0.5 * (box.lo[1] + box.hi[1]);
    double margin = 0.02 * (box.hi[2] - box.lo[2]) + 1e-3;
    double top = box.hi[2] + margin, depth = box.hi[2] - box.lo[2] + 2.0 * margin;
    double rows[4][4] = {
        {right[0] / half, right[1] / half, right[2] / half, -cx / half},
        {up[0] / half, up[1] / half, up[2] / half, -cy / half},
        {-l[0] / depth, -l[1] / depth, -l[2] / depth, top / depth},
        {0, 0, 0, 1},
    };
    double m[16];
    from_rows(rows, m);
    to_float(m, v->light_view_proj);
    v->shadow_texel = 2.0 * half / shadow_map_size;
    v->shadow_depth = depth;

    /* A shadow can fall on the ground. */
    v->key_above_ground = dot(l, v->up) > 0.02;
}

void cvk_view_resolve(const cvk_render_desc* desc, const cvk_build* build, const double gravity[3],
                      const cvk_view_colliders* colliders, const cvk_view_fit* fit, uint32_t shadow_map_size,
                      cvk_view* v)
{
    memset(v, 0, sizeof *v);
    to_double(desc->up, v->up);
    normalize(v->up);
    to_double(desc->key.direction, v->key_direction);
    normalize(v->key_direction);
    to_double(desc->fill.direction, v->fill_direction);
    normalize(v->fill_direction);
    v->fov_y = desc->fov_y;
    v->width = desc->size[0];
    v->height = desc->size[1];
    v->aspect = (double)desc->size[0] / desc->size[1];
    cvk_reach_box(build, gravity, &v->reach);
    if (colliders)
        add_colliders(colliders, &v->reach);

    double lowest = INFINITY, size = 0.0;
    for (int c = 0; c < 8; c++) {
        double p[3];
        box_corner(&v->reach, c, p);
        lowest = fmin(lowest, dot(p, v->up));
    }
    for (int k = 0; k < 3; k++)
        size = fmax(size, v->reach.hi[k] - v->reach.lo[k]);
    size = fmax(size, 1e-3);
    v->ground_height = desc->auto_ground_height ? lowest - 0.05 * size : desc->ground_height;
    if (desc->auto_ground_height && colliders && colliders->ground_plane)
        v->ground_height = colliders->ground_plane_height;
    /* A quarter of the power of ten nearest the scene's size: 25 cm squares for a 1 m cloth. */
    v->ground_tile = 0.25 * pow(10.0, round(log10(size)));
    double reference[3] = {fabs(v->up[0]) < 0.9 ? 1.0 : 0.0, fabs(v->up[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    cross(v->up, reference, v->ground_axes[0]);
    normalize(v->ground_axes[0]);
    cross(v->up, v->ground_axes[0], v->ground_axes[1]);
    for (int a = 0; a < 2; a++)
        for (int k = 0; k < 3; k++)
            v->ground_axes[a][k] /= v->ground_tile;

    if (desc->fit && fit && fit->count > 0) {
        cvk_box_empty(&v->reach);
        for (uint64_t i = 0; i < fit->count; i++)
            cvk_box_add(&v->reach, &fit->xyz[3 * i]);
        fit_camera(desc, fit, v);
    } else {
        place_camera(desc, v);
    }
    depth_range(v, colliders);
    camera_matrix(v);
    double spread = desc->soft_shadows ? tan(0.5 * desc->key_angle * PI / 180.0) : 0.0;
    light_matrix(v, shadow_map_size, spread);
}
