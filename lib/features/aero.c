/* Air on the device: the tables of the two air passes, their set and ops, and the host
   reference of the same forces (lib/features/aero.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "features/aero.h"
#include "core/error.h"
#include "core/vec3.h"
#include "shared/layout.h"
#include "contact/collide.h"
#include "plan/state.h"

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
#define TEXEL {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 0}
static const cvk_binding aero_bindings[CVK_AERO_BINDING_COUNT] = {
    [CVK_AERO_BINDING_FRAME] = STORAGE,        [CVK_AERO_BINDING_POSITIONS] = TEXEL,
    [CVK_AERO_BINDING_U] = TEXEL,              [CVK_AERO_BINDING_TRIANGLES] = TEXEL,
    [CVK_AERO_BINDING_COEFFICIENTS] = STORAGE, [CVK_AERO_BINDING_FORCES] = STORAGE,
    [CVK_AERO_BINDING_INCIDENCE] = TEXEL,      [CVK_AERO_BINDING_EXTERNAL] = STORAGE,
    [CVK_AERO_BINDING_FORCES_READ] = TEXEL,
};
#undef STORAGE
#undef TEXEL

static const double two_pi = 6.283185307179586;
static const double degrees = 0.017453292519943295;

void cvk_aero_wind_at(const cvk_wind_desc* w, double t, double out[3])
{
    double tau = two_pi / w->gusts.period * t;
    double speed = 1.0 + w->gusts.amplitude * 0.5 * (sin(tau) + sin(1.618 * tau + 1.0));
    double turn = w->gusts.jitter * degrees * sin(0.73 * tau + 2.0);
    double c = cos(turn), s = sin(turn);
    const float* v = w->velocity;
    out[0] = speed * (c * v[0] + s * v[2]);
    out[1] = speed * v[1];
    out[2] = speed * (c * v[2] - s * v[0]);
}

/* uvec4 per triangle (internal corners, cloth) and the free particles' triangle lists. */
static cvk_result make_tables(cvk_sim* s, cvk_aero* a, cvk_error* error)
{
    const cvk_build* b = &s->build;
    uint32_t tc = b->triangle_count, nf = b->free_count;
    uint32_t* tris = calloc(4 * (size_t)(tc ? tc : 1), sizeof(uint32_t));
    uint32_t* inc = calloc((size_t)nf + 1 + 3 * (size_t)tc, sizeof(uint32_t));
    cvk_result r = tris && inc ? CVK_SUCCESS
                               : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                                          "out of host memory for the air's tables");
    for (uint32_t c = 0; r == CVK_SUCCESS && c < b->cloth_count; c++)
        for (uint32_t t = b->cloths[c].first_triangle;
             t < b->cloths[c].first_triangle + b->cloths[c].triangle_count; t++) {
            for (int k = 0; k < 3; k++) {
                uint32_t p = b->internal_of[b->triangles[3 * (size_t)t + k]];
                tris[4 * (size_t)t + k] = p;
                if (p < nf)
                    inc[p + 1]++;
            }
            tris[4 * (size_t)t + 3] = c;
        }
    for (uint32_t p = 0; r == CVK_SUCCESS && p < nf; p++)
        inc[p + 1] += inc[p];
    uint32_t* fill = r == CVK_SUCCESS ? calloc(nf ? nf : 1, sizeof(uint32_t)) : NULL;
    if (r == CVK_SUCCESS && !fill)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the air's tables");
    for (uint32_t t = 0; r == CVK_SUCCESS && t < tc; t++) /* ascending: a fixed order */
        for (int k = 0; k < 3; k++) {
            uint32_t p = tris[4 * (size_t)t + k];
            if (p < nf)
                inc[nf + 1 + inc[p] + fill[p]++] = t;
        }
    size_t inc_count = (size_t)nf + 1 + (nf ? inc[nf] : 0);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->triangles, 16u * (VkDeviceSize)tc, "air triangles", tris,
                                error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->incidence, 4u * (VkDeviceSize)inc_count,
                                "air incidence", inc, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->forces, 16u * (VkDeviceSize)tc, "air forces", NULL,
                                error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &a->coefficient_buffer,
                                16u * (VkDeviceSize)b->cloth_count, "air coefficients",
                                a->coefficients, error);
    free(fill);
    free(tris);
    free(inc);
    struct {
        const cvk_buffer* buffer;
        VkFormat format;
        VkBufferView* view;
    } views[] = {
        {&a->triangles, VK_FORMAT_R32G32B32A32_UINT, &a->view_triangles},
        {&a->incidence, VK_FORMAT_R32_UINT, &a->view_incidence},
        {&a->forces, VK_FORMAT_R32G32B32A32_SFLOAT, &a->view_forces},
    };
    for (size_t i = 0; r == CVK_SUCCESS && i < sizeof views / sizeof views[0]; i++)
        r = cvk_buffer_view_create(s->device.context, views[i].buffer, views[i].format, views[i].view,
                                   error);
    return r;
}

static cvk_result make_external(cvk_sim* s, cvk_aero* a, cvk_error* error)
{
    VkDeviceSize size = a->enabled ? 16u * (VkDeviceSize)s->build.free_count : 16u;
    float* zeros = calloc(size / 4 ? size / 4 : 4, sizeof(float));
    cvk_result r = zeros ? cvk_device_make_buffer(&s->device, &a->external, size, "air displacements", zeros,
                                               error)
                         : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                                    "out of host memory for the air's displacements");
    free(zeros);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_view_create(s->device.context, &a->external, VK_FORMAT_R32G32B32A32_SFLOAT,
                                   &a->view_external, error);
    return r;
}

cvk_result cvk_aero_create(cvk_sim* s, const cvk_scene_desc* scene, cvk_error* error)
{
    cvk_aero* a = s->aero;
    *a = (cvk_aero){.enabled = scene->wind.enabled, .wind = scene->wind};
    cvk_result r = make_external(s, a, error);
    if (r != CVK_SUCCESS || !a->enabled)
        return r;
    a->coefficients = calloc(4 * (size_t)scene->cloth_count, sizeof(float));
    if (!a->coefficients)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the air");
    float half_rho = 0.5f * scene->air_density;
    for (uint32_t c = 0; c < scene->cloth_count; c++) {
        const cvk_aero_desc* d = &scene->cloths[c].aero;
        float* k = &a->coefficients[4 * (size_t)c];
        k[0] = half_rho * d->drag;
        k[1] = half_rho * d->lift;
        k[2] = half_rho * d->friction;
    }
    r = make_tables(s, a, error);
    if (r == CVK_SUCCESS)
        r = cvk_descriptors_create(s->device.context, aero_bindings, CVK_AERO_BINDING_COUNT, 1,
                                   VK_SHADER_STAGE_COMPUTE_BIT, sizeof(cvk_aero_push),
                                   &a->descriptors, error);
    return r; /* on failure cvk_sim_destroy calls cvk_aero_destroy */
}

void cvk_aero_destroy(cvk_sim* s)
{
    cvk_aero* a = s->aero;
    cvk_descriptors_destroy(s->device.context, &a->descriptors);
    VkBufferView views[] = {a->view_external, a->view_triangles, a->view_incidence,
                            a->view_forces};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++)
        if (views[i])
            vkDestroyBufferView(s->device.context->device, views[i], NULL);
    cvk_buffer* buffers[] = {&a->triangles, &a->coefficient_buffer, &a->forces, &a->incidence,
                             &a->external};
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++)
        cvk_buffer_destroy(s->device.context, buffers[i]);
    free(a->coefficients);
    *a = (cvk_aero){0};
}

void cvk_aero_bind(cvk_sim* s, VkBufferView u)
{
    cvk_aero* a = s->aero;
    if (!a->enabled)
        return;
    const cvk_resource res[CVK_AERO_BINDING_COUNT] = {
        [CVK_AERO_BINDING_FRAME] = {.buffer = &s->collide->frame},
        [CVK_AERO_BINDING_POSITIONS] = {.view = s->view_positions},
        [CVK_AERO_BINDING_U] = {.view = u},
        [CVK_AERO_BINDING_TRIANGLES] = {.view = a->view_triangles},
        [CVK_AERO_BINDING_COEFFICIENTS] = {.buffer = &a->coefficient_buffer},
        [CVK_AERO_BINDING_FORCES] = {.buffer = &a->forces},
        [CVK_AERO_BINDING_INCIDENCE] = {.view = a->view_incidence},
        [CVK_AERO_BINDING_EXTERNAL] = {.buffer = &a->external},
        [CVK_AERO_BINDING_FORCES_READ] = {.view = a->view_forces},
    };
    cvk_descriptors_write(s->device.context, &a->descriptors, 0, res);
    a->bound = true;
}

cvk_result cvk_aero_add_passes(cvk_sim* s, cvk_plan* plan, cvk_error* error)
{
    cvk_aero* a = s->aero;
    const cvk_build* b = &s->build;
    if (!a->enabled || b->free_count == 0 || b->triangle_count == 0)
        return CVK_SUCCESS;
    if (!a->bound)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "wind: this solver does not apply wind");
    /* The colliders' or the attachments' pass, when there is one, counted this substep. */
    bool counted = (s->collide->colliding && s->collide->collider_count > 0) ||
                   b->attached_count > 0;
    const cvk_gusts_desc* g = &a->wind.gusts;
    cvk_aero_push push = {
        .count = b->triangle_count, .counted = counted ? 1u : 0u, .dt = s->params.dt,
        .wind = {a->wind.velocity[0], a->wind.velocity[1], a->wind.velocity[2], 0.0f},
        .gusts = {g->amplitude, (float)(two_pi / g->period), (float)(g->jitter * degrees), 0.0f},
    };
    uint32_t pass = cvk_plan_pass(plan, "wind");
    cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_AERO_TRIANGLES,
                                   a->descriptors.pipeline_layout, a->descriptors.sets[0],
                                   CVK_DOMAIN_TRIANGLES, 0, b->triangle_count, &push, sizeof push);
    if (op)
        snprintf(op->note, sizeof op->note, "drag, friction, lift per triangle");
    push.count = b->free_count;
    op = cvk_plan_dispatch(plan, pass, CVK_PIPE_AERO_GATHER, a->descriptors.pipeline_layout,
                           a->descriptors.sets[0], CVK_DOMAIN_PARTICLES, 0, b->free_count, &push,
                           sizeof push);
    if (op)
        snprintf(op->note, sizeof op->note, "h^2 F / m per free particle%s",
                 counted ? "" : ", step += 1");
    return cvk_plan_check(plan, error);
}

/* ---- the host reference ---------------------------------------------------------------- */

static void sub3(const double a[3], const double b[3], double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = a[k] - b[k];
}


/* A third of the force on triangle (p[0], p[1], p[2]) with the cloth's coefficients k. */
static void triangle_force(const float* x, const float* u, const uint32_t p[3], const double k[3],
                           const double wind[3], double h, double out[3])
{
    double corner[3][3], v[3] = {wind[0], wind[1], wind[2]};
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 3; c++) {
            corner[i][c] = x[3 * (size_t)p[i] + c];
            v[c] -= u[3 * (size_t)p[i] + c] / (3.0 * h);
        }
    double e1[3], e2[3], n[3];
    sub3(corner[1], corner[0], e1);
    sub3(corner[2], corner[0], e2);
    cvk_cross3d(e1, e2, n);
    double twice_area = sqrt(cvk_dot3d(n, n));
    memset(out, 0, 3 * sizeof(double));
    if (!(twice_area > 0.0))
        return;
    for (int c = 0; c < 3; c++)
        n[c] /= twice_area;
    double vn = cvk_dot3d(v, n), vt[3], vxn[3], across[3];
    for (int c = 0; c < 3; c++)
        vt[c] = v[c] - vn * n[c];
    double speed = sqrt(cvk_dot3d(v, v)), tangential = sqrt(cvk_dot3d(vt, vt));
    cvk_cross3d(v, n, vxn);
    cvk_cross3d(vxn, v, across);
    double across_length = sqrt(cvk_dot3d(across, across));
    for (int c = 0; c < 3; c++) {
        out[c] = k[0] * fabs(vn) * vn * n[c] + k[2] * speed * vt[c];
        if (across_length > 0.0)
            out[c] += k[1] * vn * tangential * across[c] / across_length;
        out[c] *= twice_area / 6.0;
    }
}

void cvk_aero_forces_host(const cvk_sim* s, const float* x, const float* u, double t,
                          double* force)
{
    const cvk_build* b = &s->build;
    const cvk_aero* a = s->aero;
    memset(force, 0, 3 * (size_t)b->particle_count * sizeof(double));
    if (!a->enabled)
        return;
    double wind[3];
    cvk_aero_wind_at(&a->wind, t, wind);
    for (uint32_t c = 0; c < b->cloth_count; c++) {
        const float* kf = &a->coefficients[4 * (size_t)c];
        double k[3] = {kf[0], kf[1], kf[2]};
        for (uint32_t t3 = b->cloths[c].first_triangle;
             t3 < b->cloths[c].first_triangle + b->cloths[c].triangle_count; t3++) {
            uint32_t p[3];
            for (int i = 0; i < 3; i++)
                p[i] = b->internal_of[b->triangles[3 * (size_t)t3 + i]];
            double f[3];
            triangle_force(x, u, p, k, wind, s->params.dt, f);
            for (int i = 0; i < 3; i++)
                for (int d = 0; d < 3 && p[i] < b->free_count; d++)
                    force[3 * (size_t)p[i] + d] += f[d];
        }
    }
}

cvk_result cvk_aero_read_forces(cvk_sim* s, float* force, cvk_error* error)
{
    const cvk_build* b = &s->build;
    memset(force, 0, 3 * (size_t)b->particle_count * sizeof(float));
    if (!s->aero->enabled || b->free_count == 0)
        return CVK_SUCCESS;
    float* ext = malloc(16 * (size_t)b->free_count);
    if (!ext)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the air's forces");
    cvk_result r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &s->aero->external,
                                       ext, 16 * (VkDeviceSize)b->free_count, error);
    double h = s->params.dt;
    for (uint32_t p = 0; r == CVK_SUCCESS && p < b->free_count; p++)
        for (int c = 0; c < 3; c++)
            force[3 * (size_t)p + c] = (float)((double)ext[4 * (size_t)p + c] * b->mass[p] / (h * h));
    free(ext);
    return r;
}
