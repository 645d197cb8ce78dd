/* The contact module's objects: the scene's collision settings resolved, colliders copied,
   mesh colliders turned into fields, the contact set's buffers filled once. Its passes are in
   collide_passes.c, the host's view of the shapes in collide_host.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/collide.h"
#include "core/error.h"
#include "scene/scene.h"
#include "shared/layout.h"
#include "plan/state.h"
#include "core/u64_map.h"

/* Half the shortest structural rest length (any spring's when a cloth has no structural
   ones): particles then keep a spacing's distance from each other across layers. */
static float default_thickness(const cvk_build* b)
{
    float shortest = INFINITY, any = INFINITY;
    for (uint32_t i = 0; i < b->spring_count; i++) {
        float rest = b->springs[i].rest;
        if (!(rest > 0.0f))
            continue;
        any = fminf(any, rest);
        if (b->springs[i].type == CVK_SPRING_STRUCTURAL)
            shortest = fminf(shortest, rest);
    }
    float length = isfinite(shortest) ? shortest : any;
    return isfinite(length) ? 0.5f * length : 0.005f;
}

static char* copy_string(const char* s)
{
    if (!s)
        return NULL;
    size_t n = strlen(s) + 1;
    char* c = malloc(n);
    if (c)
        memcpy(c, s, n);
    return c;
}

static void free_colliders(cvk_collide* c)
{
    for (uint32_t i = 0; c->colliders && i < c->collider_count; i++) {
        free((char*)c->colliders[i].name);
        free((char*)c->colliders[i].file);
        free((char*)c->colliders[i].texture);
        free((cvk_keyframe*)c->colliders[i].motion.keyframes);
        if (c->sdfs)
            cvk_sdf_destroy(&c->sdfs[i]);
    }
    free(c->colliders);
    free(c->sdfs);
    c->colliders = NULL;
    c->sdfs = NULL;
}

/* Deep copies: the scene's strings and keyframes need not outlive the simulation. */
static cvk_result copy_colliders(cvk_collide* c, const cvk_scene_desc* scene, cvk_error* error)
{
    uint32_t n = scene->collider_count;
    c->colliders = calloc(n ? n : 1, sizeof *c->colliders);
    c->sdfs = calloc(n ? n : 1, sizeof *c->sdfs);
    if (!c->colliders || !c->sdfs)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the colliders");
    for (uint32_t i = 0; i < n; i++) {
        const cvk_collider_desc* in = &scene->colliders[i];
        cvk_collider_desc* out = &c->colliders[i];
        *out = *in;
        out->name = copy_string(in->name);
        out->file = copy_string(in->file);
        out->texture = copy_string(in->texture);
        size_t kf = in->motion.keyframe_count * sizeof(cvk_keyframe);
        cvk_keyframe* keyframes = kf ? malloc(kf) : NULL;
        if (kf && keyframes)
            memcpy(keyframes, in->motion.keyframes, kf);
        out->motion.keyframes = keyframes;
        c->collider_count = i + 1; /* from here on, free_colliders frees this one's copies */
        if ((in->name && !out->name) || (in->file && !out->file) || (in->texture && !out->texture) ||
            (kf && !keyframes))
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the colliders");
        if (out->friction < 0.0f)
            out->friction = c->friction;
        if (out->static_friction < 0.0f)
            out->static_friction = fmaxf(c->static_friction, out->friction);
    }
    c->collider_count = n;
    return CVK_SUCCESS;
}

/* Signed distance fields of the mesh colliders, fine enough for the cloth's thickness. */
static cvk_result read_meshes(cvk_collide* c, cvk_error* error)
{
    for (uint32_t i = 0; i < c->collider_count; i++) {
        const cvk_collider_desc* d = &c->colliders[i];
        if (d->type != CVK_COLLIDER_MESH)
            continue;
        char key[CVK_KEY_PATH_MAX];
        cvk_key_path(key, "colliders.%u.file", i);
        cvk_result r = cvk_sdf_from_mesh_file(d->file, &d->transform, 96, 0.5f * c->thickness,
                                              key, &c->sdfs[i], error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

static void quat_xyzw(const float wxyz[4], float out[4])
{
    float q[4];
    cvk_quat_normalize(wxyz, q);
    out[0] = q[1];
    out[1] = q[2];
    out[2] = q[3];
    out[3] = q[0];
}

static void set3(float out[4], const float v[3], float w)
{
    out[0] = v[0];
    out[1] = v[1];
    out[2] = v[2];
    out[3] = w;
}

/* The shape of one collider as the device reads it. */
static cvk_gpu_collider gpu_shape(const cvk_collide* c, uint32_t i, uint32_t keyframe_first,
                                  uint32_t sdf_first)
{
    const cvk_collider_desc* d = &c->colliders[i];
    cvk_gpu_collider g = {0};
    g.type = (uint32_t)d->type;
    g.keyframe_first = keyframe_first;
    g.keyframe_count = d->motion.keyframe_count;
    g.loop = d->motion.loop ? 1u : 0u;
    g.friction = d->friction;
    g.static_friction = d->static_friction;
    g.sdf_first = sdf_first;
    g.c[3] = 1.0f;
    switch (d->type) {
    case CVK_COLLIDER_PLANE: {
        float n[3] = {d->normal[0], d->normal[1], d->normal[2]};
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++)
            n[k] = len > 0.0f ? n[k] / len : (k == 1 ? 1.0f : 0.0f);
        set3(g.a, d->point, 0.0f);
        set3(g.b, n, 0.0f);
        break;
    }
    case CVK_COLLIDER_SPHERE:
        set3(g.a, d->center, d->radius);
        break;
    case CVK_COLLIDER_BOX:
        set3(g.a, d->center, 0.0f);
        set3(g.b, d->half_extents, 0.0f);
        quat_xyzw(d->rotation, g.c);
        break;
    case CVK_COLLIDER_CAPSULE:
        set3(g.a, d->a, d->radius);
        set3(g.b, d->b, 0.0f);
        break;
    case CVK_COLLIDER_FUNNEL:
        set3(g.a, d->apex, d->funnel_a);
        g.b[0] = d->height;
        break;
    case CVK_COLLIDER_MESH:
    case CVK_COLLIDER_TYPE_COUNT: {
        const cvk_sdf* f = &c->sdfs[i];
        set3(g.a, f->origin, f->voxel);
        for (int k = 0; k < 3; k++)
            g.b[k] = (float)f->dims[k];
        break;
    }
    }
    return g;
}

typedef struct contact_tables {
    cvk_gpu_collider* shapes;
    float* keyframes; /* 8 floats per keyframe */
    float* sdf;
    uint32_t keyframe_count;
    uint64_t sdf_count;
} contact_tables;

static cvk_result make_collider_tables(const cvk_collide* c, contact_tables* t, cvk_error* error)
{
    for (uint32_t i = 0; i < c->collider_count; i++) {
        t->keyframe_count += c->colliders[i].motion.keyframe_count;
        const cvk_sdf* f = &c->sdfs[i];
        t->sdf_count += (uint64_t)f->dims[0] * f->dims[1] * f->dims[2];
    }
    t->shapes = calloc(c->collider_count ? c->collider_count : 1, sizeof *t->shapes);
    t->keyframes = calloc(8 * (size_t)(t->keyframe_count ? t->keyframe_count : 1), sizeof(float));
    t->sdf = calloc(t->sdf_count ? t->sdf_count : 1, sizeof(float));
    if (!t->shapes || !t->keyframes || !t->sdf)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the colliders");
    uint32_t k = 0;
    uint64_t v = 0;
    for (uint32_t i = 0; i < c->collider_count; i++) {
        const cvk_collider_desc* d = &c->colliders[i];
        const cvk_sdf* f = &c->sdfs[i];
        t->shapes[i] = gpu_shape(c, i, k, (uint32_t)v);
        cvk_motion_pack(&d->motion, &t->keyframes[8 * (size_t)k]);
        k += d->motion.keyframe_count;
        uint64_t n = (uint64_t)f->dims[0] * f->dims[1] * f->dims[2];
        if (n)
            memcpy(&t->sdf[v], f->values, n * sizeof(float));
        v += n;
    }
    return CVK_SUCCESS;
}

static void free_tables(contact_tables* t)
{
    free(t->shapes);
    free(t->keyframes);
    free(t->sdf);
}

/* The poses over the substep that ends after `step` substeps of dt (both at time 0 before the
   first), as the recorded work (collider_poses.comp) leaves them: the renderer draws the colliders
   at pose 1, so a state written at a later time (a snapshot) shows them where its clock says. */
void cvk_collide_poses_at(const cvk_collide* c, uint64_t step, double dt, cvk_gpu_pose* poses)
{
    double t1 = (double)step * dt, t0 = step > 0 ? (double)(step - 1) * dt : 0.0;
    for (uint32_t i = 0; i < c->collider_count; i++) {
        cvk_pose p0 = cvk_collide_pose(c, i, t0), p1 = cvk_collide_pose(c, i, t1);
        quat_xyzw(p0.rotation, poses[i].rotation0);
        set3(poses[i].translation0, p0.translation, 0.0f);
        quat_xyzw(p1.rotation, poses[i].rotation1);
        set3(poses[i].translation1, p1.translation, 0.0f);
    }
}

/* ---- cloth tables for particle–triangle contact ---------------------------------------- */

typedef struct cloth_tables {
    uint32_t* triangles;      /* 4 per triangle: internal indices, border bits */
    uint32_t* incident;       /* particle_count + 1 offsets, then triangle ids */
    size_t incident_count;
    uint32_t edge_count;
    uint32_t* edges;          /* 4 per edge: its ends (lower first), 0, 0 */
    uint32_t* triangle_edges; /* 4 per triangle: edge k from corner k to k + 1, 0 */
    uint32_t* particle_edges; /* particle_count + 1 offsets, then edge ids */
    size_t particle_edges_count;
} cloth_tables;

static void free_cloth_tables(cloth_tables* t)
{
    free(t->triangles);
    free(t->incident);
    free(t->edges);
    free(t->triangle_edges);
    free(t->particle_edges);
}

/* Offsets from counts (in place, out[0..n]), then the lists placed by a cursor. */
static void prefix(uint32_t* table, uint32_t n)
{
    uint32_t sum = 0;
    for (uint32_t p = 0; p <= n; p++) {
        uint32_t count = table[p];
        table[p] = sum;
        sum += count;
    }
}

/* w of each triangle: bit k set where no triangle runs the edge from corner k + 1 back to
   corner k (a border, or a neighbour wound the other way), so that corner meets the edge only
   here and only as the one before it (pd_contact.glsl, edges_off_shells). */
static bool mark_borders(uint32_t* triangles, uint32_t tc)
{
    cvk_u64_map directed = {0};
    if (!cvk_u64_map_init(&directed, 3 * (size_t)tc)) {
        cvk_u64_map_free(&directed);
        return false;
    }
    for (uint32_t i = 0; i < tc; i++)
        for (int k = 0; k < 3; k++) {
            uint64_t key = (uint64_t)triangles[4 * (size_t)i + k] << 32 |
                           triangles[4 * (size_t)i + (k + 1) % 3];
            directed.key[cvk_u64_map_slot(&directed, key)] = key;
        }
    for (uint32_t i = 0; i < tc; i++)
        for (int k = 0; k < 3; k++) {
            uint64_t back = (uint64_t)triangles[4 * (size_t)i + (k + 1) % 3] << 32 |
                            triangles[4 * (size_t)i + k];
            if (directed.key[cvk_u64_map_slot(&directed, back)] != back)
                triangles[4 * (size_t)i + 3] |= 1u << k;
        }
    cvk_u64_map_free(&directed);
    return true;
}

/* The triangles' edges, each once (numbered in order of first appearance), which edges each
   triangle has, and the edges at each particle. */
static bool make_edges(cloth_tables* t, uint32_t n, uint32_t tc)
{
    cvk_u64_map ids = {0};
    t->edges = malloc(12 * (size_t)(tc ? tc : 1) * sizeof(uint32_t));
    t->triangle_edges = calloc(4 * (size_t)(tc ? tc : 1), sizeof(uint32_t));
    bool ok = t->edges && t->triangle_edges && cvk_u64_map_init(&ids, 3 * (size_t)tc);
    for (uint32_t i = 0; ok && i < tc; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = t->triangles[4 * (size_t)i + k], b = t->triangles[4 * (size_t)i + (k + 1) % 3];
            uint64_t key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
            size_t slot = cvk_u64_map_slot(&ids, key);
            if (ids.key[slot] != key) {
                ids.key[slot] = key;
                ids.value[slot] = t->edge_count;
                uint32_t* e = &t->edges[4 * (size_t)t->edge_count++];
                e[0] = a < b ? a : b;
                e[1] = a < b ? b : a;
                e[2] = e[3] = 0;
            }
            t->triangle_edges[4 * (size_t)i + k] = (uint32_t)ids.value[slot];
        }
    cvk_u64_map_free(&ids);
    t->particle_edges_count = (size_t)n + 1 + 2 * (size_t)t->edge_count;
    t->particle_edges = ok ? calloc(t->particle_edges_count, sizeof(uint32_t)) : NULL;
    uint32_t* cursor = ok ? calloc((size_t)n + 1, sizeof(uint32_t)) : NULL;
    if (!t->particle_edges || !cursor) {
        free(cursor);
        return false;
    }
    for (uint32_t e = 0; e < t->edge_count; e++) {
        t->particle_edges[t->edges[4 * (size_t)e]]++;
        t->particle_edges[t->edges[4 * (size_t)e + 1]]++;
    }
    prefix(t->particle_edges, n);
    memcpy(cursor, t->particle_edges, ((size_t)n + 1) * sizeof(uint32_t));
    for (uint32_t e = 0; e < t->edge_count; e++)
        for (int k = 0; k < 2; k++) {
            uint32_t v = t->edges[4 * (size_t)e + k];
            t->particle_edges[n + 1 + cursor[v]++] = e;
        }
    free(cursor);
    return true;
}

static cvk_result make_cloth_tables(const cvk_build* b, cloth_tables* t, cvk_error* error)
{
    uint32_t n = b->particle_count, tc = b->triangle_count;
    t->incident_count = (size_t)n + 1 + 3 * (size_t)tc;
    t->triangles = calloc(4 * (size_t)(tc ? tc : 1), sizeof(uint32_t));
    t->incident = calloc(t->incident_count, sizeof(uint32_t));
    uint32_t* cursor = calloc((size_t)n + 1, sizeof(uint32_t));
    bool ok = t->triangles && t->incident && cursor;
    /* Every triangle under each of its corners, in triangle order: detection reaches a
       triangle through its corners (shaders/contact/contact_detect.comp). */
    for (uint32_t i = 0; ok && i < tc; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = b->internal_of[b->triangles[3 * (size_t)i + k]];
            t->triangles[4 * (size_t)i + k] = v;
            t->incident[v]++;
        }
    ok = ok && mark_borders(t->triangles, tc) && make_edges(t, n, tc);
    if (!ok) {
        free(cursor);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "out of host memory for the contact tables");
    }
    prefix(t->incident, n);
    memcpy(cursor, t->incident, ((size_t)n + 1) * sizeof(uint32_t));
    for (uint32_t i = 0; i < tc; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = t->triangles[4 * (size_t)i + k];
            t->incident[n + 1 + cursor[v]++] = i;
        }
    free(cursor);
    return CVK_SUCCESS;
}

/* ---- buffers and the contact set -------------------------------------------------------- */

#define STORAGE {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 0}
#define UNIFORM {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 0}
#define TEXEL {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 0}
static const cvk_binding contact_bindings[CVK_CONTACT_BINDING_COUNT] = {
    [CVK_CONTACT_BINDING_FRAME] = STORAGE,
    [CVK_CONTACT_BINDING_PARAMS] = STORAGE,
    [CVK_CONTACT_BINDING_SHAPES] = STORAGE,
    [CVK_CONTACT_BINDING_KEYFRAMES] = STORAGE,
    [CVK_CONTACT_BINDING_POSES] = STORAGE,
    [CVK_CONTACT_BINDING_SDF] = STORAGE,
    [CVK_CONTACT_BINDING_TRIANGLES] = TEXEL,
    [CVK_CONTACT_BINDING_INCIDENT] = TEXEL,
    [CVK_CONTACT_BINDING_EDGES] = TEXEL,
    [CVK_CONTACT_BINDING_CONTACTS] = STORAGE,
    [CVK_CONTACT_BINDING_POSITIONS] = TEXEL,
    [CVK_CONTACT_BINDING_PARAMS_UNIFORM] = UNIFORM,
    [CVK_CONTACT_BINDING_SHAPES_UNIFORM] = UNIFORM,
    [CVK_CONTACT_BINDING_POSES_UNIFORM] = UNIFORM,
    [CVK_CONTACT_BINDING_CONTACTS_READ] = TEXEL,
    [CVK_CONTACT_BINDING_SEARCHED] = STORAGE,
    [CVK_CONTACT_BINDING_TRIANGLE_EDGES] = TEXEL,
    [CVK_CONTACT_BINDING_EDGE_CONTACTS] = STORAGE,
    [CVK_CONTACT_BINDING_EDGE_CONTACTS_READ] = TEXEL,
    [CVK_CONTACT_BINDING_NEAREST] = STORAGE,
    [CVK_CONTACT_BINDING_LISTS] = STORAGE,
    [CVK_CONTACT_BINDING_SEARCHED_READ] = TEXEL,
    [CVK_CONTACT_BINDING_PARTICLE_EDGES] = TEXEL,
    [CVK_CONTACT_BINDING_PREVIOUS] = STORAGE,
    [CVK_CONTACT_BINDING_SIDES] = STORAGE,
    [CVK_CONTACT_BINDING_SIDES_READ] = TEXEL,
    [CVK_CONTACT_BINDING_MIDPOINTS] = STORAGE,
    [CVK_CONTACT_BINDING_INSTANCES] = TEXEL,
    [CVK_CONTACT_BINDING_CENTROIDS] = STORAGE,
    [CVK_CONTACT_BINDING_CELLS] = STORAGE,
    [CVK_CONTACT_BINDING_CELL_POOL] = STORAGE,
    [CVK_CONTACT_BINDING_CELL_POOL_READ] = TEXEL,
    [CVK_CONTACT_BINDING_EDGE_ENDS_READ] = TEXEL,
    [CVK_CONTACT_BINDING_NEAREST_READ] = TEXEL,
    [CVK_CONTACT_BINDING_PREVIOUS_READ] = TEXEL,
};
#undef STORAGE
#undef UNIFORM
#undef TEXEL

static cvk_result create_collider_buffers(cvk_sim* s, cvk_collide* c, cvk_error* error)
{
    contact_tables t = {0};
    /* at least the uniform arrays' size (shaders/contact/collide.glsl); more colliders than they
       hold are read from the storage buffers, and the uniform bindings get a stub */
    uint32_t n = c->collider_count > CVK_UNIFORM_COLLIDERS ? c->collider_count : CVK_UNIFORM_COLLIDERS;
    cvk_result stub = CVK_SUCCESS;
    if (c->collider_count > CVK_UNIFORM_COLLIDERS)
        stub = cvk_device_make_buffer(&s->device, &c->uniform_stub,
                                      CVK_UNIFORM_COLLIDERS * sizeof(cvk_gpu_collider),
                                      "collider uniform stub", NULL, error);
    if (stub != CVK_SUCCESS)
        return stub;
    cvk_gpu_pose* poses = calloc(n, sizeof *poses);
    cvk_result r = poses ? make_collider_tables(c, &t, error)
                         : cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                                    "out of host memory for the colliders");
    if (r == CVK_SUCCESS) {
        cvk_collide_poses_at(c, 0, s->params.dt, poses);
        r = cvk_device_make_buffer(&s->device, &c->poses, n * sizeof(cvk_gpu_pose), "collider poses", poses, error);
    }
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &c->shapes, n * sizeof(cvk_gpu_collider), "collider shapes", NULL,
                        error);
    if (r == CVK_SUCCESS && c->collider_count)
        r = cvk_device_upload(&s->device, &c->shapes, t.shapes, c->collider_count * sizeof(cvk_gpu_collider),
                           error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &c->keyframes, 32u * (VkDeviceSize)(t.keyframe_count ? t.keyframe_count : 1),
                        "collider keyframes", t.keyframes, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &c->sdf_values, 4u * (VkDeviceSize)(t.sdf_count ? t.sdf_count : 1),
                        "collider distance fields", t.sdf, error);
    free_tables(&t);
    free(poses);
    return r;
}

/* The longest edge of any cloth triangle at rest. */
static float longest_edge(const cvk_build* b)
{
    float longest = 0.0f;
    for (uint32_t t = 0; t < b->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const float* p = &b->position[3 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + k]]];
            const float* q =
                &b->position[3 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + (k + 1) % 3]]];
            float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            longest = fmaxf(longest, sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
    return longest;
}

/* Each particle's bound 0 where it starts (detection at the first substep sets them), and its
   position a substep before: where it is. */
static cvk_result upload_start(cvk_sim* s, cvk_collide* c, cvk_error* error)
{
    const cvk_build* b = &s->build;
    float* x = malloc(16u * (size_t)(b->particle_count ? b->particle_count : 1));
    if (!x)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the contact state");
    for (uint32_t p = 0; p < b->particle_count; p++) {
        for (int k = 0; k < 3; k++)
            x[4 * (size_t)p + k] = b->position[3 * (size_t)p + k];
        x[4 * (size_t)p + 3] = 0.0f;
    }
    VkDeviceSize bytes = 16u * (VkDeviceSize)b->particle_count;
    cvk_result r = cvk_device_upload(&s->device, &c->searched, x, bytes, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_upload(&s->device, &c->previous, x, bytes, error);
    free(x);
    return r;
}

typedef struct buffer_job {
    cvk_buffer* buffer;
    VkDeviceSize bytes;
    bool self_only;     /* made only with self-contact, else with the triangle tables (16 bytes
                           otherwise) */
    const char* label;
    const void* data;
} buffer_job;

/* The particles' instances (zeros with one), and with self-contact and several instances the
   edges' and the triangles' (from their first corners'): the hashes' salts (collide_passes.c). */
static cvk_result create_instance_buffers(cvk_sim* s, cvk_collide* c, const cloth_tables* t,
                                          cvk_error* error)
{
    const cvk_build* b = &s->build;
    cvk_result r = cvk_device_make_buffer(&s->device, &c->instances,
                                          4u * (VkDeviceSize)(b->particle_count ? b->particle_count : 1),
                                          "particle instances", c->instance_of, error);
    if (r == CVK_SUCCESS && !c->instance_of) /* one instance: 0 for every particle */
        r = cvk_device_clear_buffer(&s->device, &c->instances, error);
    bool salted = c->self && c->instance_of;
    struct {
        cvk_buffer* buffer;
        const uint32_t* table; /* 4 per item, its first end or corner first */
        uint32_t count;
        const char* what;
    } kinds[] = {{&c->edge_instances, t->edges, t->edge_count, "edges"},
                 {&c->triangle_instances, t->triangles, b->triangle_count, "triangles"}};
    for (size_t k = 0; r == CVK_SUCCESS && k < sizeof kinds / sizeof kinds[0]; k++) {
        VkDeviceSize count = kinds[k].count ? kinds[k].count : 1;
        uint32_t* e = salted ? malloc(count * sizeof *e) : NULL;
        if (salted && !e)
            r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "instances: out of host memory for %u %s",
                         kinds[k].count, kinds[k].what);
        for (uint32_t i = 0; e && i < kinds[k].count; i++)
            e[i] = c->instance_of[kinds[k].table[4 * (size_t)i]];
        if (r == CVK_SUCCESS)
            r = cvk_device_make_buffer(&s->device, kinds[k].buffer, salted ? 4u * count : 16u,
                                       kinds[k].what, e, error);
        free(e);
    }
    return r;
}

/* What the buffers hold before the first detection: no contacts (all bits set), no nearest
   distance (0x7f7f7f7f: 3.4e38 as a float, beyond any distance), empty work lists, cell lists
   (the decision writes their command at each substep) and pairs by corner (the first
   substep's detection, frame.force, writes them before any contact pass reads them). */
static cvk_result fill_initial(cvk_sim* s, cvk_collide* c, cvk_error* error)
{
    struct {
        cvk_buffer* buffer;
        unsigned char byte;
    } fills[] = {{&c->contacts, 0xff}, {&c->edge_contacts, 0xff}, {&c->nearest, 0x7f},
                 {&c->lists, 0}, {&c->cells, 0}, {&c->sides, 0}};
    cvk_result r = CVK_SUCCESS;
    for (size_t i = 0; r == CVK_SUCCESS && i < sizeof fills / sizeof fills[0]; i++)
        r = cvk_device_fill_buffer(&s->device, fills[i].buffer, fills[i].byte, error);
    return r;
}

static cvk_result create_cloth_buffers(cvk_sim* s, cvk_collide* c, cvk_error* error)
{
    const cvk_build* b = &s->build;
    cloth_tables t = {0};
    cvk_result r = CVK_SUCCESS;
    bool tables = c->self || cvk_collide_has_funnels(c);
    if (tables)
        r = make_cloth_tables(b, &t, error);
    if (r == CVK_SUCCESS && c->self &&
        (b->triangle_count > CVK_MAX_FEATURES || t.edge_count > CVK_MAX_FEATURES ||
         b->particle_count > CVK_MAX_FEATURES))
        r = cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                     "collision.self: the cloths have %u triangles and %u edges, more than the "
                     "%u self-contact can address", b->triangle_count, t.edge_count,
                     CVK_MAX_FEATURES);
    c->edge_count = t.edge_count;
    VkDeviceSize n = b->particle_count ? b->particle_count : 1;
    VkDeviceSize tc = b->triangle_count ? b->triangle_count : 1;
    VkDeviceSize ec = t.edge_count ? t.edge_count : 1;
    buffer_job jobs[] = {
        {&c->triangles, 16u * tc, false, "contact triangles", t.triangles},
        {&c->incident, 4u * t.incident_count, false, "triangles by corner", t.incident},
        {&c->edges, 16u * ec, true, "contact edges", t.edges},
        {&c->triangle_edges, 16u * tc, true, "edges by triangle", t.triangle_edges},
        {&c->particle_edges, 4u * t.particle_edges_count, true, "edges by end", t.particle_edges},
        {&c->contacts, 4u * CVK_CONTACTS_PER_PARTICLE * n, true, "contacts", NULL},
        {&c->edge_contacts, 4u * CVK_CONTACTS_PER_EDGE * ec, true, "edge contacts", NULL},
        {&c->nearest, 4u * (n + 2u * ec + 2u * CVK_EDGE_BUCKET * ec), true,
         "nearest distances and the edges' pairs", NULL},
        {&c->searched, 16u * n, true, "positions at detection and bounds", NULL},
        {&c->previous, 16u * n, true, "positions a substep before", NULL},
        {&c->lists, 4u * (CVK_LIST_HEADER + (VkDeviceSize)n + ec), true, "work lists", NULL},
        {&c->sides, 4u * n * (1u + 2u * CVK_SIDES_PER_PARTICLE), true, "pairs by corner", NULL},
        {&c->midpoints, 16u * ec, true, "edge midpoints", NULL},
        {&c->centroids, 16u * tc, true, "triangle centroids", NULL},
        {&c->cells, 4u * (CVK_CELLS_HEADER + 4u * ec), true, "edge cells", NULL},
        /* the edges' ends at detection (8 words an edge), then the cell lists: one storage
           buffer, as the implicit family's pipeline layouts take all 32 that lavapipe allows
           a stage */
        {&c->cell_pool, 4u * (8u + CVK_CELL_POOL_PER_EDGE) * ec, true,
         "edge ends and cell lists", NULL},
    };
    for (size_t i = 0; r == CVK_SUCCESS && i < sizeof jobs / sizeof jobs[0]; i++) {
        bool small = jobs[i].self_only ? !c->self : !tables;
        r = cvk_device_make_buffer(&s->device, jobs[i].buffer, small ? 16u : jobs[i].bytes,
                                   jobs[i].label, small ? NULL : jobs[i].data, error);
    }
    if (r == CVK_SUCCESS)
        r = fill_initial(s, c, error);
    if (r == CVK_SUCCESS)
        r = create_instance_buffers(s, c, &t, error);
    if (r == CVK_SUCCESS && c->self)
        r = upload_start(s, c, error);
    free_cloth_tables(&t);
    struct {
        const cvk_buffer* buffer;
        VkFormat format;
        VkBufferView* view;
    } views[] = {
        {&c->triangles, VK_FORMAT_R32G32B32A32_UINT, &c->view_triangles},
        {&c->incident, VK_FORMAT_R32_UINT, &c->view_incident},
        {&c->contacts, VK_FORMAT_R32_UINT, &c->view_contacts},
        {&c->searched, VK_FORMAT_R32G32B32A32_SFLOAT, &c->view_searched},
        {&c->edges, VK_FORMAT_R32G32B32A32_UINT, &c->view_edges},
        {&c->triangle_edges, VK_FORMAT_R32G32B32A32_UINT, &c->view_triangle_edges},
        {&c->particle_edges, VK_FORMAT_R32_UINT, &c->view_particle_edges},
        {&c->edge_contacts, VK_FORMAT_R32_UINT, &c->view_edge_contacts},
        {&c->sides, VK_FORMAT_R32_UINT, &c->view_sides},
        {&c->instances, VK_FORMAT_R32_UINT, &c->view_instances},
        {&c->cell_pool, VK_FORMAT_R32_UINT, &c->view_cell_pool},
        {&c->cell_pool, VK_FORMAT_R32G32B32A32_UINT, &c->view_edge_ends},
        {&c->nearest, VK_FORMAT_R32_UINT, &c->view_nearest},
        {&c->previous, VK_FORMAT_R32G32B32A32_SFLOAT, &c->view_previous},
    };
    for (size_t i = 0; r == CVK_SUCCESS && i < sizeof views / sizeof views[0]; i++)
        r = cvk_buffer_view_create(s->device.context, views[i].buffer, views[i].format, views[i].view,
                                   error);
    return r;
}

static cvk_result create_params(cvk_sim* s, cvk_collide* c, bool kinematic, cvk_error* error)
{
    const cvk_build* b = &s->build;
    cvk_gpu_contact_params p = {
        .collider_count = c->collider_count,
        .particle_count = b->particle_count,
        .free_count = b->free_count,
        .triangle_count = b->triangle_count,
        .thickness = c->thickness,
        .friction = c->friction,
        .static_friction = c->static_friction,
        .dt = s->params.dt,
        .radius = c->radius,
        .gamma = CVK_BOUND_GAMMA,
        .redetect = CVK_REDETECT_FRACTION,
        .detection_interval = c->detection_interval,
        .edge_count = c->edge_count,
        /* a kinematic particle (pinned, attached) cannot follow a common shift */
        .shift = b->free_count == b->particle_count && !kinematic,
        .longest = c->longest,
        .cloth_count = b->cloth_count,
        .instance_colliders = c->instance_colliders,
    };
    /* the frame state, then the motion bounds (empty) */
    struct {
        cvk_gpu_frame frame;
        cvk_gpu_motion_bounds bounds;
    } frame = {
        .frame = {.search = 1, .force = 1},
        .bounds = {.e_low_x = CVK_MOTION_LOW_EMPTY, .e_low_y = CVK_MOTION_LOW_EMPTY,
                   .e_low_z = CVK_MOTION_LOW_EMPTY, .e_high_x = CVK_MOTION_HIGH_EMPTY,
                   .e_high_y = CVK_MOTION_HIGH_EMPTY, .e_high_z = CVK_MOTION_HIGH_EMPTY,
                   .v_low_x = CVK_MOTION_LOW_EMPTY, .v_low_y = CVK_MOTION_LOW_EMPTY,
                   .v_low_z = CVK_MOTION_LOW_EMPTY, .v_high_x = CVK_MOTION_HIGH_EMPTY,
                   .v_high_y = CVK_MOTION_HIGH_EMPTY, .v_high_z = CVK_MOTION_HIGH_EMPTY},
    };
    _Static_assert(sizeof frame == sizeof(cvk_gpu_frame) + sizeof(cvk_gpu_motion_bounds),
                   "the frame buffer: the frame state, then the bounds, as std430 lays them out");
    cvk_result r = cvk_device_make_buffer(&s->device, &c->params, sizeof p, "contact parameters", &p, error);
    if (r == CVK_SUCCESS)
        r = cvk_device_make_buffer(&s->device, &c->frame, sizeof frame, "frame state", &frame, error);
    return r;
}

static cvk_result create_set(cvk_sim* s, cvk_collide* c, cvk_error* error)
{
    cvk_result r = cvk_descriptors_create(s->device.context, contact_bindings, CVK_CONTACT_BINDING_COUNT,
                                          1, VK_SHADER_STAGE_COMPUTE_BIT,
                                          sizeof(cvk_contact_push), &c->descriptors, error);
    if (r != CVK_SUCCESS)
        return r;
    c->set_layout = c->descriptors.set_layout;
    c->set = c->descriptors.sets[0];
    const cvk_resource res[CVK_CONTACT_BINDING_COUNT] = {
        [CVK_CONTACT_BINDING_FRAME] = {.buffer = &c->frame},
        [CVK_CONTACT_BINDING_PARAMS] = {.buffer = &c->params},
        [CVK_CONTACT_BINDING_SHAPES] = {.buffer = &c->shapes},
        [CVK_CONTACT_BINDING_KEYFRAMES] = {.buffer = &c->keyframes},
        [CVK_CONTACT_BINDING_POSES] = {.buffer = &c->poses},
        [CVK_CONTACT_BINDING_SDF] = {.buffer = &c->sdf_values},
        [CVK_CONTACT_BINDING_TRIANGLES] = {.view = c->view_triangles},
        [CVK_CONTACT_BINDING_INCIDENT] = {.view = c->view_incident},
        [CVK_CONTACT_BINDING_EDGES] = {.view = c->view_edges},
        [CVK_CONTACT_BINDING_CONTACTS] = {.buffer = &c->contacts},
        [CVK_CONTACT_BINDING_POSITIONS] = {.view = s->view_positions},
        [CVK_CONTACT_BINDING_PARAMS_UNIFORM] = {.buffer = &c->params},
        [CVK_CONTACT_BINDING_SHAPES_UNIFORM] = {.buffer = c->uniform_stub.size ? &c->uniform_stub : &c->shapes},
        [CVK_CONTACT_BINDING_POSES_UNIFORM] = {.buffer = c->uniform_stub.size ? &c->uniform_stub : &c->poses},
        [CVK_CONTACT_BINDING_CONTACTS_READ] = {.view = c->view_contacts},
        [CVK_CONTACT_BINDING_SEARCHED] = {.buffer = &c->searched},
        [CVK_CONTACT_BINDING_TRIANGLE_EDGES] = {.view = c->view_triangle_edges},
        [CVK_CONTACT_BINDING_EDGE_CONTACTS] = {.buffer = &c->edge_contacts},
        [CVK_CONTACT_BINDING_EDGE_CONTACTS_READ] = {.view = c->view_edge_contacts},
        [CVK_CONTACT_BINDING_NEAREST] = {.buffer = &c->nearest},
        [CVK_CONTACT_BINDING_LISTS] = {.buffer = &c->lists},
        [CVK_CONTACT_BINDING_SEARCHED_READ] = {.view = c->view_searched},
        [CVK_CONTACT_BINDING_PARTICLE_EDGES] = {.view = c->view_particle_edges},
        [CVK_CONTACT_BINDING_PREVIOUS] = {.buffer = &c->previous},
        [CVK_CONTACT_BINDING_SIDES] = {.buffer = &c->sides},
        [CVK_CONTACT_BINDING_SIDES_READ] = {.view = c->view_sides},
        [CVK_CONTACT_BINDING_MIDPOINTS] = {.buffer = &c->midpoints},
        [CVK_CONTACT_BINDING_INSTANCES] = {.view = c->view_instances},
        [CVK_CONTACT_BINDING_CENTROIDS] = {.buffer = &c->centroids},
        [CVK_CONTACT_BINDING_CELLS] = {.buffer = &c->cells},
        [CVK_CONTACT_BINDING_CELL_POOL] = {.buffer = &c->cell_pool},
        [CVK_CONTACT_BINDING_CELL_POOL_READ] = {.view = c->view_cell_pool},
        [CVK_CONTACT_BINDING_EDGE_ENDS_READ] = {.view = c->view_edge_ends},
        [CVK_CONTACT_BINDING_NEAREST_READ] = {.view = c->view_nearest},
        [CVK_CONTACT_BINDING_PREVIOUS_READ] = {.view = c->view_previous},
    };
    cvk_descriptors_write(s->device.context, &c->descriptors, 0, res);
    return CVK_SUCCESS;
}

cvk_result cvk_collide_create(cvk_sim* s, const cvk_scene_desc* scene, cvk_error* error)
{
    cvk_collide* c = s->collide;
    *c = (cvk_collide){0};
    c->self = scene->collision.self;
    c->colliding = c->self || scene->collider_count > 0;
    c->thickness = scene->collision.thickness > 0.0f ? scene->collision.thickness
                                                     : default_thickness(&s->build);
    c->radius = cvk_collision_radius(&scene->collision, c->thickness);
    c->detection_interval = cvk_collision_detection_interval(&scene->collision);
    c->friction = scene->collision.friction;
    c->static_friction = fmaxf(scene->collision.static_friction, c->friction);
    c->longest = 1.5f * longest_edge(&s->build);
    c->types = cvk_scene_collider_types(scene) |
               (scene->collider_count > CVK_UNIFORM_COLLIDERS ? CVK_COLLIDERS_IN_STORAGE : 0u);
    cvk_result r = copy_colliders(c, scene, error);
    if (r == CVK_SUCCESS)
        r = cvk_collide_find_instances(s, c, scene, error);
    if (r == CVK_SUCCESS)
        c->types |= cvk_collide_runs(c, &c->runs) |
                    (c->instance_count == 1 ? CVK_COLLIDERS_ONE_INSTANCE : 0u);
    if (r == CVK_SUCCESS)
        r = read_meshes(c, error);
    if (r == CVK_SUCCESS && c->self)
        cvk_collide_split_substeps(s, c, scene->solver.method == CVK_METHOD_IMPLICIT);
    if (r == CVK_SUCCESS)
        r = create_collider_buffers(s, c, error);
    if (r == CVK_SUCCESS)
        r = create_cloth_buffers(s, c, error);
    if (r == CVK_SUCCESS)
        r = create_params(s, c, scene->attachment_count > 0, error);
    if (r == CVK_SUCCESS)
        r = create_set(s, c, error);
    if (r == CVK_SUCCESS && c->self)
        r = cvk_collide_create_detection(s, error);
    return r;
}

void cvk_collide_destroy(cvk_sim* s)
{
    cvk_collide* c = s->collide;
    cvk_context* ctx = s->device.context;
    if (c->face_hash.capacity)
        cvk_hash_destroy(ctx, &c->face_hash);
    if (c->edge_hash.capacity)
        cvk_hash_destroy(ctx, &c->edge_hash);
    cvk_descriptors_destroy(ctx, &c->descriptors);
    VkBufferView views[] = {c->view_triangles, c->view_incident, c->view_contacts,
                            c->view_searched, c->view_edges, c->view_triangle_edges,
                            c->view_particle_edges, c->view_edge_contacts, c->view_sides,
                            c->view_instances, c->view_cell_pool, c->view_edge_ends,
                            c->view_nearest, c->view_previous};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++)
        if (views[i])
            vkDestroyBufferView(ctx->device, views[i], NULL);
    cvk_buffer* buffers[] = {&c->frame, &c->poses, &c->shapes, &c->keyframes, &c->sdf_values,
                             &c->params, &c->triangles, &c->incident, &c->edges,
                             &c->triangle_edges, &c->particle_edges, &c->contacts,
                             &c->edge_contacts, &c->nearest, &c->searched, &c->previous,
                             &c->lists, &c->sides, &c->midpoints, &c->centroids,
                             &c->cells, &c->cell_pool,
                             &c->instances, &c->edge_instances, &c->triangle_instances,
                             &c->uniform_stub};
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; i++)
        cvk_buffer_destroy(ctx, buffers[i]);
    free_colliders(c);
    free(c->instance_of);
    *c = (cvk_collide){0};
}

