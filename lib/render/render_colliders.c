/* The simulation's colliders as the renderer draws them: every collider's triangles at rest
   (collider_mesh.h) in one vertex and one index buffer, made once; each frame the vertex
   shaders move them by the pose the simulation's own recorded work left in its poses buffer
   (pose 1: the end of the last substep), so a frame submitted again draws moving colliders
   without a host write. A static plane facing up, when the ground is drawn at an automatic
   height or at the plane's own, is the ground itself rather than a second surface on top of
   it; when it has a texture the composite pass draws that on the ground (render.c's
   ground_texture constants, shaders/render/composite.frag), to the horizon.

   A collider's texture (material.texture) has no texture coordinates to follow: each vertex
   also carries its position and normal in the collider's texture frame, which the pose moves
   with the collider, and lit_cloth.frag (built with COLLIDER) projects the texture along that
   frame's three axes, blended by the normal (triplanar mapping). The frame is a box's own
   (its centre and rotation, x along its longest side), a plane's own (its point; y along its
   normal, x along the scene's x, or z where the normal is near x), and the scene's axes at rest
   for the round shapes, the funnel and a mesh collider (a mesh file's texture coordinates are
   not used). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/collider_mesh.h"
#include "core/error.h"
#include "scene/motion.h"
#include "render/render_internal.h"
#include "sim/sim.h"

/* A plane collider is drawn as a square this many times the cloths' size: well past the
   frame of the automatic camera, and still finite, so the depth range stays tight. */
#define PLANE_EXTENT_SCALE 8.0
/* A collider's material.roughness r in [0.1, 1] as a Blinn-Phong highlight: exponent 8 / r²
   (800 to 8) and strength 0.06 / r (0.6 to 0.06), so the highlight spreads and dims together;
   the default 0.5 gives exponent 32 and strength 0.12. */
#define HIGHLIGHT_EXPONENT 8.0f
#define HIGHLIGHT_STRENGTH 0.06f

/* A plane whose normal is within about 0.8° of up can be the ground. */
#define GROUND_COS 0.9999
/* A plane within this distance (m) of a given ground height is at that height. */
#define GROUND_HEIGHT_TOLERANCE 1e-5

static double length3(const float v[3])
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

/* The height (m along up) of a static plane collider facing up, when it becomes the ground. */
static bool ground_plane(const cvk_renderer* rd, const cvk_collider_desc* c, double* height)
{
    if (c->type != CVK_COLLIDER_PLANE || c->motion.keyframe_count > 0 || !rd->desc.ground)
        return false;
    double n = length3(c->normal), u = length3(rd->desc.up);
    if (n == 0.0 || u == 0.0)
        return false;
    double along = 0.0, h = 0.0;
    for (int k = 0; k < 3; k++) {
        along += (double)c->normal[k] * rd->desc.up[k] / (n * u);
        h += (double)c->point[k] * rd->desc.up[k] / u;
    }
    *height = h;
    /* A ground at a given height is this plane when they coincide: drawing the plane too would
       only cover the ground with the same surface (at 4x MSAA, most of the image's cost). */
    if (!rd->desc.auto_ground_height && fabs(h - rd->desc.ground_height) > GROUND_HEIGHT_TOLERANCE)
        return false;
    return along >= GROUND_COS;
}

void cvk_render_plane_frame(const cvk_collider_desc* c, double x[3], double up[3], double z[3])
{
    double len = length3(c->normal);
    for (int k = 0; k < 3; k++)
        up[k] = len > 0.0 ? c->normal[k] / len : k == 1;
    double seed[3] = {fabs(up[0]) < 0.9, 0.0, fabs(up[0]) < 0.9 ? 0.0 : 1.0};
    double along = seed[0] * up[0] + seed[2] * up[2], xl = 0.0;
    for (int k = 0; k < 3; k++) {
        x[k] = seed[k] - along * up[k];
        xl += x[k] * x[k];
    }
    for (int k = 0; k < 3; k++)
        x[k] /= sqrt(xl);
    z[0] = x[1] * up[2] - x[2] * up[1];
    z[1] = x[2] * up[0] - x[0] * up[2];
    z[2] = x[0] * up[1] - x[1] * up[0];
}

/* Vertex (p, n) of collider c at rest in the collider's texture frame (tp, tn). */
static void texture_frame(const cvk_collider_desc* c, const float p[3], const float n[3], float tp[3], float tn[3])
{
    if (c->type == CVK_COLLIDER_BOX) {
        float q[4], inverse[4], lp[3], ln[3], d[3] = {p[0] - c->center[0], p[1] - c->center[1], p[2] - c->center[2]};
        cvk_quat_normalize(c->rotation, q);
        inverse[0] = q[0];
        for (int k = 1; k < 4; k++)
            inverse[k] = -q[k];
        cvk_quat_rotate(inverse, d, lp);
        cvk_quat_rotate(inverse, n, ln);
        /* The frame's x along the box's longest side, y along its shortest, z the third: the
           texture's u (a wood grain's direction) runs along the long side of every face that
           has one (a table top, a leg, an apron). */
        const float* h = c->half_extents;
        int longest = 0, shortest = 0;
        for (int k = 1; k < 3; k++) {
            if (h[k] > h[longest])
                longest = k;
            if (h[k] < h[shortest] || (h[k] == h[shortest] && shortest == longest))
                shortest = k;
        }
        if (shortest == longest)
            shortest = (longest + 1) % 3;
        int order[3] = {longest, shortest, 3 - longest - shortest};
        for (int k = 0; k < 3; k++) {
            tp[k] = lp[order[k]];
            tn[k] = ln[order[k]];
        }
        return;
    }
    if (c->type == CVK_COLLIDER_PLANE) {
        double x[3], up[3], z[3];
        cvk_render_plane_frame(c, x, up, z);
        const double* axes[3] = {x, up, z};
        for (int a = 0; a < 3; a++) {
            double dp = 0.0, dn = 0.0;
            for (int k = 0; k < 3; k++) {
                dp += ((double)p[k] - c->point[k]) * axes[a][k];
                dn += (double)n[k] * axes[a][k];
            }
            tp[a] = (float)dp;
            tn[a] = (float)dn;
        }
        return;
    }
    for (int k = 0; k < 3; k++) { /* a loop: GCC's -Warray-bounds misreads the memcpy once inlined */
        tp[k] = p[k];
        tn[k] = n[k];
    }
}

/* The mesh's box under a pose, added to `drawn` too. */
static cvk_box posed_box(const cvk_collider_mesh* m, const cvk_pose* pose, cvk_box* drawn)
{
    cvk_box box;
    cvk_box_empty(&box);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float p[3];
        cvk_pose_apply(pose, &m->xyz[3 * (size_t)v], p);
        double d[3] = {p[0], p[1], p[2]};
        cvk_box_add(&box, d);
    }
    cvk_box_add(drawn, box.lo);
    cvk_box_add(drawn, box.hi);
    return box;
}

/* Where a collider is drawn at rest and at each keyframe: finite ones into the camera's
   boxes, all into the drawn box. */
static cvk_result frame_collider(cvk_render_colliders* rc, const cvk_collider_desc* c, const cvk_collider_mesh* m,
                                 cvk_error* error)
{
    uint32_t poses = 1 + c->motion.keyframe_count;
    bool finite = c->type != CVK_COLLIDER_PLANE;
    if (finite) {
        cvk_box* grown = realloc(rc->boxes, ((size_t)rc->framing.box_count + poses) * sizeof *grown);
        if (!grown)
            return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the colliders' bounds");
        rc->boxes = grown;
    }
    for (uint32_t i = 0; i < poses; i++) {
        double t = i == 0 ? 0.0 : c->motion.keyframes[i - 1].time;
        cvk_pose pose = cvk_motion_pose(&c->motion, t);
        cvk_box box = posed_box(m, &pose, &rc->framing.drawn);
        if (finite)
            rc->boxes[rc->framing.box_count++] = box;
    }
    rc->framing.boxes = rc->boxes;
    return CVK_SUCCESS;
}

/* Distance from p to the segment a..b. */
static double point_segment_distance(const double p[3], const double a[3], const double b[3])
{
    double ab[3], ap[3], along = 0.0, len2 = 0.0;
    for (int k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ap[k] = p[k] - a[k];
        along += ab[k] * ap[k];
        len2 += ab[k] * ab[k];
    }
    double t = len2 > 0.0 ? fmin(fmax(along / len2, 0.0), 1.0) : 0.0, d2 = 0.0;
    for (int k = 0; k < 3; k++)
        d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
    return sqrt(d2);
}

/* A sphere's (a point) or a capsule's axis. */
typedef struct axis_segment {
    double a[3], b[3];
} axis_segment;

static double axis_distance(const double eye[3], const void* to)
{
    const axis_segment* axis = to;
    return point_segment_distance(eye, axis->a, axis->b);
}

/* The least distance from the camera's eye (the scene's, or along its keyframes' path) to the
   axis of a sphere or a capsule under `pose`. */
static double eye_distance(const cvk_renderer* rd, const cvk_collider_desc* c, const cvk_pose* pose)
{
    bool capsule = c->type == CVK_COLLIDER_CAPSULE;
    float a[3], b[3];
    cvk_pose_apply(pose, capsule ? c->a : c->center, a);
    cvk_pose_apply(pose, capsule ? c->b : c->center, b);
    axis_segment axis = {{a[0], a[1], a[2]}, {b[0], b[1], b[2]}};
    double eye[3] = {rd->desc.eye[0], rd->desc.eye[1], rd->desc.eye[2]};
    return cvk_render_eye_least(rd, eye, axis_distance, &axis);
}

/* The most pixels a sphere's or a capsule's radius can span in the picture: from the nearest
   the eye comes to its surface, at rest and at each of its keyframes, taken as half as far (it
   moves between keyframes, and the picture's width may be the larger); 0 (unknown: the finest
   mesh) where the camera is placed automatically or the eye reaches the surface. */
static double radius_pixels(const cvk_renderer* rd, const cvk_collider_desc* c)
{
    const cvk_render_desc* d = &rd->desc;
    if (c->type != CVK_COLLIDER_SPHERE && c->type != CVK_COLLIDER_CAPSULE)
        return 0.0;
    if (d->fit || (rd->eye_path.keyframe_count == 0 && d->auto_eye))
        return 0.0;
    /* the angle a pixel spans at the middle of the picture */
    double pixel = 2.0 * tan(0.5 * d->fov_y * 3.14159265358979323846 / 180.0) / d->size[1];
    double least = INFINITY;
    for (uint32_t i = 0; i <= c->motion.keyframe_count; i++) {
        cvk_pose pose = cvk_motion_pose(&c->motion, i == 0 ? 0.0 : c->motion.keyframes[i - 1].time);
        least = fmin(least, eye_distance(rd, c, &pose) - c->radius);
    }
    if (!(least > 0.0) || !(pixel > 0.0))
        return 0.0;
    return 2.0 * c->radius / (least * pixel);
}

/* Every drawn collider's mesh (the ground plane has none); `meshes` has one slot per
   collider. */
static cvk_result make_meshes(cvk_renderer* rd, const double gravity[3], cvk_collider_mesh* meshes,
                              cvk_error* error)
{
    const cvk_collide* collide = rd->mesh->sim->collide;
    cvk_render_colliders* rc = &rd->colliders;
    cvk_box cloths;
    cvk_reach_box(&rd->mesh->sim->build, gravity, &cloths);
    float focus[3];
    double size = 1e-3;
    for (int k = 0; k < 3; k++) {
        focus[k] = (float)(0.5 * (cloths.lo[k] + cloths.hi[k]));
        size = fmax(size, cloths.hi[k] - cloths.lo[k]);
    }
    for (uint32_t i = 0; i < collide->collider_count; i++) {
        const cvk_collider_desc* c = &collide->colliders[i];
        double height;
        if (ground_plane(rd, c, &height)) {
            if (!rc->framing.ground_plane || height > rc->framing.ground_plane_height) {
                rc->framing.ground_plane_height = height;
                rc->ground_texture = c->texture ? i + 1 : 0;
            }
            rc->framing.ground_plane = true;
            continue;
        }
        const cvk_sdf* sdf = c->type == CVK_COLLIDER_MESH ? &collide->sdfs[i] : NULL;
        cvk_result r = cvk_collider_mesh_make(c, sdf, focus, (float)(PLANE_EXTENT_SCALE * size),
                                              radius_pixels(rd, c), &meshes[i], error);
        if (r == CVK_SUCCESS)
            r = frame_collider(rc, c, &meshes[i], error);
        if (r != CVK_SUCCESS)
            return r;
    }
    return CVK_SUCCESS;
}

/* The meshes into the two buffers, and one draw each. */
static cvk_result upload(cvk_renderer* rd, const cvk_collider_mesh* meshes, uint32_t count, cvk_error* error)
{
    cvk_render_colliders* rc = &rd->colliders;
    uint64_t vertices = 0, indices = 0;
    uint32_t draws = 0;
    for (uint32_t i = 0; i < count; i++) {
        vertices += meshes[i].vertex_count;
        indices += 3u * (uint64_t)meshes[i].triangle_count;
        draws += meshes[i].triangle_count > 0;
    }
    if (draws == 0)
        return CVK_SUCCESS;
    if (vertices > UINT32_MAX || indices > UINT32_MAX)
        return cvk_fail(error, CVK_ERROR_DEVICE_LIMIT,
                        "colliders: %llu vertices and %llu indices are more than 32-bit indices can draw",
                        (unsigned long long)vertices, (unsigned long long)indices);
    rc->draws = calloc(draws, sizeof *rc->draws);
    if (!rc->draws)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the collider draws");
    /* Written once by the host and read by vertex input: host memory spares a staging copy. */
    cvk_result r = cvk_buffer_create(rd->context, vertices * 12 * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                     CVK_MEMORY_HOST, "collider vertices", &rc->vertices, error);
    if (r == CVK_SUCCESS)
        r = cvk_buffer_create(rd->context, indices * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                              CVK_MEMORY_HOST, "collider indices", &rc->indices, error);
    if (r != CVK_SUCCESS)
        return r;
    float* xyzn = rc->vertices.mapped;
    uint32_t* index = rc->indices.mapped;
    uint32_t base = 0, first = 0;
    const cvk_collide* collide = rd->mesh->sim->collide;
    for (uint32_t i = 0; i < count; i++) {
        const cvk_collider_mesh* m = &meshes[i];
        if (m->triangle_count == 0)
            continue;
        const cvk_collider_desc* c = &collide->colliders[i];
        for (uint32_t v = 0; v < m->vertex_count; v++) {
            float* out = &xyzn[12 * (size_t)(base + v)];
            memcpy(out, &m->xyz[3 * (size_t)v], 3 * sizeof(float));
            memcpy(out + 3, &m->normals[3 * (size_t)v], 3 * sizeof(float));
            texture_frame(c, out, out + 3, out + 6, out + 9);
        }
        for (uint32_t k = 0; k < 3 * m->triangle_count; k++)
            index[first + k] = base + m->triangles[k];
        float rough = c->roughness;
        rc->draws[rc->draw_count++] = (cvk_collider_draw){
            .first_index = first,
            .index_count = 3 * m->triangle_count,
            .collider = i,
            .color = {c->color[0], c->color[1], c->color[2], 1.0f},
            .highlight = {HIGHLIGHT_STRENGTH / rough, HIGHLIGHT_EXPONENT / (rough * rough)},
            .textured = c->texture != NULL,
            .closed = c->type == CVK_COLLIDER_SPHERE || c->type == CVK_COLLIDER_CAPSULE || c->type == CVK_COLLIDER_BOX,
            .repeats = 1.0f / c->texture_scale,
        };
        base += m->vertex_count;
        first += 3 * m->triangle_count;
    }
    return CVK_SUCCESS;
}

cvk_result cvk_render_colliders_create(cvk_renderer* rd, const double gravity[3], cvk_error* error)
{
    uint32_t n = rd->mesh->sim->collide->collider_count;
    cvk_box_empty(&rd->colliders.framing.drawn);
    if (n == 0)
        return CVK_SUCCESS;
    cvk_collider_mesh* meshes = calloc(n, sizeof *meshes);
    if (!meshes)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for the collider meshes");
    cvk_result r = make_meshes(rd, gravity, meshes, error);
    if (r == CVK_SUCCESS)
        r = upload(rd, meshes, n, error);
    for (uint32_t i = 0; i < n; i++)
        cvk_collider_mesh_destroy(&meshes[i]);
    free(meshes);
    return r;
}

void cvk_render_colliders_destroy(cvk_renderer* rd)
{
    cvk_render_colliders* rc = &rd->colliders;
    cvk_buffer_destroy(rd->context, &rc->vertices);
    cvk_buffer_destroy(rd->context, &rc->indices);
    free(rc->draws);
    free(rc->boxes);
    *rc = (cvk_render_colliders){0};
}

void cvk_render_colliders_record(const cvk_renderer* rd, VkCommandBuffer cmd, bool colored)
{
    const cvk_render_colliders* rc = &rd->colliders;
    if (rc->draw_count == 0)
        return;
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &rc->vertices.buffer, &offset);
    vkCmdBindIndexBuffer(cmd, rc->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    uint32_t bound = 0;
    VkPipeline pipeline = rd->collider_pipeline; /* bound by the caller */
    for (uint32_t d = 0; d < rc->draw_count; d++) {
        const cvk_collider_draw* draw = &rc->draws[d];
        if (colored) {
            /* A closed solid's back faces lie behind its front faces: culled, they cost nothing
               (a camera inside one sees through it). */
            VkPipeline wanted = draw->closed ? rd->collider_closed_pipeline : rd->collider_pipeline;
            if (wanted != pipeline) {
                vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, wanted);
                pipeline = wanted;
            }
            /* back (unused by colliders otherwise): x: the texture's repeats per metre; w stays
               0 (no back colour) */
            cvk_render_material m = {{draw->color[0], draw->color[1], draw->color[2], draw->textured ? 1.0f : 0.0f},
                                     {draw->repeats, 0.0f, 0.0f, 0.0f},
                                     {draw->highlight[0], draw->highlight[1], 0.0f, 0.0f},
                                     {0}};
            vkCmdPushConstants(cmd, rd->pipeline_layout, CVK_RENDER_PUSH_STAGES, 0, sizeof m, &m);
            cvk_render_bind_textures(rd, cmd, draw->textured ? rd->textures.collider_set_of[draw->collider] : 0,
                                     &bound);
        }
        /* The instance index is the collider's: the vertex shaders read its pose with it. */
        vkCmdDrawIndexed(cmd, draw->index_count, 1, draw->first_index, 0, draw->collider);
    }
    if (pipeline != rd->collider_pipeline)
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->collider_pipeline);
    if (bound != 0)
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, rd->pipeline_layout, 0, 1, &rd->set, 0, NULL);
}
