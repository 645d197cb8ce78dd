// The contact set and the contact responses every solver family calls inside its sweeps
// (lib/contact/collide.h). Include after shared/layout.h; define CONTACT_SET first to bind the set
// elsewhere than set 1.
//
// Colliders are handled in each collider's own frame, where a particle's motion over the
// substep is the segment from its start position (in the frame at the substep's start) to its
// end position (in the frame at the substep's end): the segment is traced against the shape
// thickened by the cloth thickness (sphere tracing on the signed distance, exact for the
// analytic shapes and a bound for the sampled mesh fields), so a particle that would cross a
// thin box or be overtaken by a fast sphere within the substep is stopped at the first touch,
// not only when it ends inside. The end position is then projected onto the tangent plane at
// the touch, and Coulomb friction takes the tangential part of the relative motion away
// (all of it while it is within mu_s times the normal correction, mu_k times it otherwise;
// Macklin et al. 2014 §6.1). Relative motion is measured in the collider's frame, so a moving
// surface carries the cloth along.

#ifndef CONTACT_SET
#define CONTACT_SET 1
#endif
#ifndef CONTACT_TYPES_ID
#define CONTACT_TYPES_ID 7
#endif
// Bit t set: the scene has colliders of type t (CVK_COLLIDER_*_ID); the others' code is
// specialised away.
// Bits 6-29: an instance's colliders as runs of one type, where the scene fixes them
// (shared/layout.h; FOR_EACH_COLLIDER).
// Bit 31 (CVK_COLLIDERS_IN_STORAGE): more colliders than the uniform arrays hold; they are read
// from the storage buffers.
layout(constant_id = CONTACT_TYPES_ID) const uint COLLIDER_TYPES = 63u;
#define HAS_TYPE(t) ((COLLIDER_TYPES & (1u << (t))) != 0u)
const uint COLLIDER_TYPE_BITS = COLLIDER_TYPES & CVK_COLLIDER_TYPE_MASK;
const bool STORAGE_COLLIDERS = (COLLIDER_TYPES & CVK_COLLIDERS_IN_STORAGE) != 0u;

layout(std140, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_PARAMS_UNIFORM) uniform ContactParamsU {
    cvk_gpu_contact_params contact_u;
};
layout(std140, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SHAPES_UNIFORM) uniform ShapesU {
    cvk_gpu_collider shapes_u[CVK_UNIFORM_COLLIDERS];
};
layout(std140, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_POSES_UNIFORM) uniform PosesU {
    cvk_gpu_pose poses_u[CVK_UNIFORM_COLLIDERS];
};
#include "contact/bounds.glsl" // the frame state, where detection saw each particle, the bounds
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_PARAMS) readonly buffer ContactParams {
    cvk_gpu_contact_params contact;
};
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SHAPES) readonly buffer Shapes {
    cvk_gpu_collider shapes[];
};
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_KEYFRAMES) readonly buffer Keyframes {
    vec4 keyframes[]; // 2 per keyframe: (time, translation), rotation (x, y, z, w)
};
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_POSES) buffer Poses {
    cvk_gpu_pose poses[];
};
// Collider k's shape and pose: from the uniform arrays, or with more colliders than they hold
// from the storage buffers (a specialisation constant: the other side compiles to nothing).
cvk_gpu_collider collider_shape(uint k)
{
    if (STORAGE_COLLIDERS)
        return shapes[k];
    return shapes_u[k];
}
cvk_gpu_pose collider_pose(uint k)
{
    if (STORAGE_COLLIDERS)
        return poses[k];
    return poses_u[k];
}
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SDF) readonly buffer Fields {
    float sdf_values[];
};
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SEARCHED) buffer Searched {
    vec4 searched[]; // per particle: where the last detection saw it, w: its bound (m)
};
// Tables read per particle in divergent loops: read-only storage texel buffers (imageLoad is an
// inline vectorised gather on lavapipe, where a storage-buffer load is a loop over the lanes and
// a uniform texel fetch a call with the live registers spilled: docs/performance.md).
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_TRIANGLES, rgba32ui) uniform readonly uimageBuffer triangles_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_INCIDENT, r32ui) uniform readonly uimageBuffer incident_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_EDGES, rgba32ui) uniform readonly uimageBuffer edges_t;
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_CONTACTS) writeonly buffer Contacts {
    uint contacts[]; // CVK_CONTACTS_PER_PARTICLE per particle: feature << 2 | kind
};
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_CONTACTS_READ, r32ui) uniform readonly uimageBuffer contacts_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_POSITIONS, rgba32f) uniform readonly imageBuffer contact_x_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_TRIANGLE_EDGES, rgba32ui) uniform readonly uimageBuffer triangle_edges_t;
// EDGES_FUSED: edge detection's phases and the bounds in one workgroup
// (contact_edges_fused.comp), whose invocations read what others wrote in the same dispatch
// through the storage buffers, coherent, after memoryBarrierBuffer() and barrier().
// DETECT_READ(stored, viewed): how a pass reads a word detection wrote — through the texel
// view (viewed) after the pass that wrote it, through the buffer (stored) in the fused dispatch.
#ifdef EDGES_FUSED
#define DETECT_COHERENT coherent
#define DETECT_WRITEONLY
#define DETECT_READ(stored, viewed) (stored)
#else
#define DETECT_COHERENT
#define DETECT_WRITEONLY writeonly
#define DETECT_READ(stored, viewed) (viewed)
#endif
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_EDGE_CONTACTS) DETECT_WRITEONLY DETECT_COHERENT buffer EdgeContacts {
    uint edge_contacts[]; // CVK_CONTACTS_PER_EDGE per edge: other edges
};
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_EDGE_CONTACTS_READ, r32ui) uniform readonly uimageBuffer edge_contacts_t;
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_NEAREST) DETECT_COHERENT buffer Nearest {
    uint nearest[]; // per particle, then per edge: the nearest distance found (float bits);
                    // then per edge: 1 where it has a pair to list (contact_edges.comp)
};
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_LISTS) DETECT_COHERENT buffer Lists {
    uint lists[]; // CVK_LIST_*: indirect commands, the particles in listed pairs
};
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_PARTICLE_EDGES, r32ui) uniform readonly uimageBuffer particle_edges_t;
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SIDES) buffer Sides {
    uint sides[]; // per particle a count, then per particle its pairs as a corner (vertex, entry)
};
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SIDES_READ, r32ui) uniform readonly uimageBuffer sides_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_INSTANCES, r32ui) uniform readonly uimageBuffer instances_t;
// Edge detection's cell lists (shared/layout.h: CVK_CELLS_*).
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_CELLS) DETECT_COHERENT buffer Cells {
    uint cells[];
};
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_CELL_POOL_READ, r32ui) uniform readonly uimageBuffer cell_pool_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_EDGE_ENDS_READ, rgba32ui) uniform readonly uimageBuffer edge_ends_t;
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_PREVIOUS) buffer Previous {
    vec4 previous[]; // per particle: its position at the start of the substep before
};
// The same nearest distances and positions a substep before, as the passes after the ones
// that wrote them read them (shared/layout.h).
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_NEAREST_READ, r32ui) uniform readonly uimageBuffer nearest_t;
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_PREVIOUS_READ, rgba32f) uniform readonly imageBuffer previous_t;
// Word i of the nearest buffer as detection's later passes read it.
#define NEAREST(i) DETECT_READ(nearest[i], imageLoad(nearest_t, int(i)).x)

uvec4 contact_triangle(uint t) { return imageLoad(triangles_t, int(t)); } // internal indices
// Triangles by corner: [p] .. [p + 1] are offsets (from particle_count + 1) of those around p.
uint contact_incident(uint i) { return imageLoad(incident_t, int(i)).x; }
uvec2 contact_edge(uint e) { return imageLoad(edges_t, int(e)).xy; } // its ends, internal
uvec4 contact_triangle_edges(uint t) { return imageLoad(triangle_edges_t, int(t)); }
// Edges by end: [p] .. [p + 1] are offsets (from particle_count + 1) of those at p.
uint particle_edge(uint i) { return imageLoad(particle_edges_t, int(i)).x; }
uint contact_entry(uint i) { return imageLoad(contacts_t, int(i)).x; }
// Pair k of particle q's side list (vertex, entry); vertex CVK_NO_CONTACT past the last.
uvec2 side_pair(uint q, uint k)
{
    uint at = contact_u.particle_count + 2u * (q * uint(CVK_SIDES_PER_PARTICLE) + k);
    return uvec2(imageLoad(sides_t, int(at)).x, imageLoad(sides_t, int(at + 1u)).x);
}
uint edge_entry(uint i)
{
    return DETECT_READ(edge_contacts[i], imageLoad(edge_contacts_t, int(i)).x);
}
vec3 contact_x(uint p) { return imageLoad(contact_x_t, int(p)).xyz; } // x_n
// The work lists (shared/layout.h): the list whose indirect command is at `command` (its count
// follows the command) emptied, and `item` appended to it, the command's workgroups (of
// per_group items) grown to cover it.
void list_clear(uint command)
{
    lists[command] = 0u;
    lists[command + 1u] = 1u;
    lists[command + 2u] = 1u;
    lists[command + 3u] = 0u;
}
uint list_start(uint command) // where its entries start
{
    return CVK_LIST_HEADER + (command == CVK_LIST_LISTED_GROUPS ? 0u : contact_u.particle_count);
}
void list_append(uint command, uint item, uint per_group)
{
    uint at = atomicAdd(lists[command + 3u], 1u);
    lists[list_start(command) + at] = item;
    atomicMax(lists[command], min(at / per_group + 1u, 65535u));
}

// Particle p's instance (the scene's copy: copies never touch one another; 0, read from
// nothing, in a scene of one: bit CVK_COLLIDERS_ONE_INSTANCE), and the range [x, y) of the
// colliders it meets: its instance's.
const bool ONE_INSTANCE = (COLLIDER_TYPES & CVK_COLLIDERS_ONE_INSTANCE) != 0u;
uint contact_instance(uint p) { return ONE_INSTANCE ? 0u : imageLoad(instances_t, int(p)).x; }
uvec2 collider_range(uint p)
{
    uint first = contact_instance(p) * contact_u.instance_colliders;
    return uvec2(first, first + contact_u.instance_colliders);
}

#include "scene/motion.glsl" // quat_rotate, motion_pose (reads keyframes, above)

// Bits of a float that order as the float does (as unsigned integers), and back: the motion
// bounds of the adaptive search (contact_check.comp, contact_decide.comp).
uint ordered(float f)
{
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}

float from_ordered(uint u)
{
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

// ---- signed distances of the shapes at rest ------------------------------------------------

float box_distance(cvk_gpu_collider c, vec3 l)
{
    vec3 b = quat_rotate_inverse(c.c, l - c.a.xyz);
    vec3 q = abs(b) - c.b.xyz;
    return length(max(q, 0.0)) + min(max(q.x, max(q.y, q.z)), 0.0);
}

vec3 box_normal(cvk_gpu_collider c, vec3 l)
{
    vec3 b = quat_rotate_inverse(c.c, l - c.a.xyz);
    vec3 q = abs(b) - c.b.xyz;
    vec3 n;
    if (max(q.x, max(q.y, q.z)) > 0.0) {
        n = max(q, 0.0) * sign(b);
    } else { // inside: out through the nearest face
        if (q.x >= q.y && q.x >= q.z)
            n = vec3(b.x >= 0.0 ? 1.0 : -1.0, 0.0, 0.0);
        else if (q.y >= q.z)
            n = vec3(0.0, b.y >= 0.0 ? 1.0 : -1.0, 0.0);
        else
            n = vec3(0.0, 0.0, b.z >= 0.0 ? 1.0 : -1.0);
    }
    return quat_rotate(c.c, normalize(n));
}

// The point of segment (a, b) nearest p.
vec3 closest_on_segment(vec3 p, vec3 a, vec3 b)
{
    vec3 ab = b - a;
    float len2 = dot(ab, ab);
    float t = len2 > 0.0 ? clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return a + t * ab;
}

vec3 capsule_closest(cvk_gpu_collider c, vec3 l)
{
    return closest_on_segment(l, c.a.xyz, c.b.xyz);
}

// The funnel: radius e^(y/a) for -height <= y <= 0 around the vertical axis through the apex.
// The nearest point of the profile curve in the particle's half-plane, by Gauss-Newton on the
// curve's height (clamped to the funnel's range, so the rims are handled too).
vec2 funnel_closest(cvk_gpu_collider c, vec3 l, out vec3 radial)
{
    vec3 d = l - c.a.xyz;
    float rho = length(d.xz);
    radial = rho > 0.0 ? vec3(d.x / rho, 0.0, d.z / rho) : vec3(1.0, 0.0, 0.0);
    float a = c.a.w, h = c.b.x;
    float s = clamp(d.y, -h, 0.0);
    for (int i = 0; i < 8; i++) {
        float r = exp(s / a), dr = r / a;
        float g = (r - rho) * dr + (s - d.y);
        s = clamp(s - g / (dr * dr + 1.0), -h, 0.0);
    }
    return vec2(exp(s / a), s) - vec2(rho, d.y); // curve point minus particle, in (rho, y)
}

float mesh_value(cvk_gpu_collider c, ivec3 i)
{
    ivec3 dims = ivec3(c.b.xyz);
    i = clamp(i, ivec3(0), dims - 1);
    return sdf_values[c.sdf_first + uint(i.x + dims.x * (i.y + dims.y * i.z))];
}

float mesh_distance(cvk_gpu_collider c, vec3 l)
{
    vec3 dims = c.b.xyz;
    vec3 g = (l - c.a.xyz) / c.a.w;
    vec3 inside = clamp(g, vec3(0.0), dims - 1.0);
    float outside = length(g - inside) * c.a.w; // beyond the grid: distance to it, added
    vec3 base = min(floor(inside), dims - 2.0);
    vec3 f = inside - base;
    ivec3 i = ivec3(base);
    float v00 = mix(mesh_value(c, i), mesh_value(c, i + ivec3(1, 0, 0)), f.x);
    float v10 = mix(mesh_value(c, i + ivec3(0, 1, 0)), mesh_value(c, i + ivec3(1, 1, 0)), f.x);
    float v01 = mix(mesh_value(c, i + ivec3(0, 0, 1)), mesh_value(c, i + ivec3(1, 0, 1)), f.x);
    float v11 = mix(mesh_value(c, i + ivec3(0, 1, 1)), mesh_value(c, i + ivec3(1, 1, 1)), f.x);
    return mix(mix(v00, v10, f.y), mix(v01, v11, f.y), f.z) + outside;
}

float shape_distance(cvk_gpu_collider c, vec3 l)
{
    if (HAS_TYPE(CVK_COLLIDER_PLANE_ID) && c.type == CVK_COLLIDER_PLANE_ID)
        return dot(c.b.xyz, l - c.a.xyz);
    if (HAS_TYPE(CVK_COLLIDER_SPHERE_ID) && c.type == CVK_COLLIDER_SPHERE_ID)
        return length(l - c.a.xyz) - c.a.w;
    if (HAS_TYPE(CVK_COLLIDER_BOX_ID) && c.type == CVK_COLLIDER_BOX_ID)
        return box_distance(c, l);
    if (HAS_TYPE(CVK_COLLIDER_CAPSULE_ID) && c.type == CVK_COLLIDER_CAPSULE_ID)
        return length(l - capsule_closest(c, l)) - c.a.w;
    if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID) && c.type == CVK_COLLIDER_FUNNEL_ID) {
        vec3 radial;
        return length(funnel_closest(c, l, radial));
    }
    if (HAS_TYPE(CVK_COLLIDER_MESH_ID))
        return mesh_distance(c, l);
    return 1e30;
}

vec3 safe_normalize(vec3 v, vec3 fallback)
{
    float len = length(v);
    return len > 1e-12 ? v / len : fallback;
}

// The outward unit normal at l (for the funnel: towards l's side of the surface).
vec3 shape_normal(cvk_gpu_collider c, vec3 l)
{
    if (HAS_TYPE(CVK_COLLIDER_PLANE_ID) && c.type == CVK_COLLIDER_PLANE_ID)
        return c.b.xyz;
    if (HAS_TYPE(CVK_COLLIDER_SPHERE_ID) && c.type == CVK_COLLIDER_SPHERE_ID)
        return safe_normalize(l - c.a.xyz, vec3(0.0, 1.0, 0.0));
    if (HAS_TYPE(CVK_COLLIDER_BOX_ID) && c.type == CVK_COLLIDER_BOX_ID)
        return box_normal(c, l);
    if (HAS_TYPE(CVK_COLLIDER_CAPSULE_ID) && c.type == CVK_COLLIDER_CAPSULE_ID)
        return safe_normalize(l - capsule_closest(c, l), vec3(0.0, 1.0, 0.0));
    if (HAS_TYPE(CVK_COLLIDER_FUNNEL_ID) && c.type == CVK_COLLIDER_FUNNEL_ID) {
        vec3 radial;
        vec2 to_curve = funnel_closest(c, l, radial);
        vec3 away = -(to_curve.x * radial + vec3(0.0, to_curve.y, 0.0));
        // On the surface itself: the curve's outward normal (away from the axis).
        float r = exp(clamp(l.y - c.a.y, -c.b.x, 0.0) / c.a.w);
        return safe_normalize(away, normalize(radial - vec3(0.0, r / c.a.w, 0.0)));
    }
    if (HAS_TYPE(CVK_COLLIDER_MESH_ID)) {
        float e = 0.5 * c.a.w;
        vec3 grad = vec3(mesh_distance(c, l + vec3(e, 0, 0)) - mesh_distance(c, l - vec3(e, 0, 0)),
                         mesh_distance(c, l + vec3(0, e, 0)) - mesh_distance(c, l - vec3(0, e, 0)),
                         mesh_distance(c, l + vec3(0, 0, e)) - mesh_distance(c, l - vec3(0, 0, e)));
        return safe_normalize(grad, vec3(0.0, 1.0, 0.0));
    }
    return vec3(0.0, 1.0, 0.0);
}

// The first point of the segment l0 -> l1 within distance r of the shape (sphere tracing), and
// the normal there; a start already within r is pushed out to r along its normal.
bool trace_segment(cvk_gpu_collider c, vec3 l0, vec3 l1, float r, out vec3 hit, out vec3 n)
{
    vec3 d = l1 - l0;
    float len = length(d);
    float s = 0.0;
    hit = l1;
    n = vec3(0.0, 1.0, 0.0);
    for (int i = 0; i < 32; i++) {
        vec3 l = l0 + s * d;
        float dist = shape_distance(c, l) - r;
        if (dist < 1e-3 * r) {
            n = shape_normal(c, l);
            hit = dist < 0.0 ? l - dist * n : l;
            return true;
        }
        if (len <= 0.0)
            return false;
        float next = s + dist / len;
        if (next >= 1.0)
            return false; // the ball of radius dist around l covers the rest of the segment
        s = next;
    }
    float dist = shape_distance(c, l1) - r; // a grazing path: decide by the end alone
    if (dist >= 0.0)
        return false;
    n = shape_normal(c, l1);
    hit = l1 - dist * n;
    return true;
}

// Friction on the end point l1 after a normal correction of `depth` along n: the tangential
// part of the motion relative to the surface (l1 - l0 in the collider's frame) is removed
// while it is within mu_s depth (static), shortened by mu_k depth otherwise (kinetic).
vec3 apply_friction(vec3 l0, vec3 l1, vec3 n, float depth, float mu, float mu_s)
{
    vec3 rel = l1 - l0;
    vec3 tangential = rel - dot(rel, n) * n;
    float t = length(tangential);
    if (t <= mu_s * depth)
        return l1 - tangential;
    return l1 - tangential * min(1.0, mu * depth / t);
}

// The path of a point that starts the substep at x0 and would end it at x0 + u, in the frame
// of a collider posed by `pose`: its start l0 (under the start pose) and its end l1 (under
// the end pose). The collider's motion is in l1 - l0.
void local_path(cvk_gpu_pose pose, vec3 x0, vec3 u, out vec3 l0, out vec3 l1)
{
    l0 = quat_rotate_inverse(pose.rotation0, x0 - pose.translation0.xyz);
    l1 = quat_rotate_inverse(pose.rotation1, x0 + u - pose.translation1.xyz);
}

// A collider's type where collide_shape is told it: ANY_TYPE (read it from the shape), or a
// run's type (bits 6-29 of COLLIDER_TYPES), a constant.
const uint ANY_TYPE = 0xffffffffu;
#define RUN_BITS(r) ((COLLIDER_TYPES >> (CVK_COLLIDER_RUNS_SHIFT + 6u * (r))) & 63u)
#define RUN_TYPE(r) ((RUN_BITS(r) & 7u) - 1u)
#define RUN_LENGTH(r) (RUN_BITS(r) >> 3u)

// Collider k's shape, its type `type` unless ANY_TYPE.
cvk_gpu_collider typed_shape(uint k, uint type)
{
    cvk_gpu_collider c = collider_shape(k);
    if (type != ANY_TYPE)
        c.type = type;
    return c;
}

// Runs EACH(k, type) for every collider k of particle p's instance, in order. A build with
// COLLIDER_RUNS defined (pd_contact.comp's and contact_check.comp's, one a run count, chosen by
// the host: cvk_collide_pipeline) loops over each run with `type` the run's, a constant, so that only
// that type's code is in the loop: llvmpipe runs the code of every type the scene has, under a
// mask, for each collider otherwise (the 40 x 40 drape without self-contact, one lavapipe
// core: the collider pass 4.4 -> 2.2 ms a frame, the same bits; docs/figures/collider-runs). Runs switched off by a
// specialisation constant instead would still be inlined and compiled, half a second each on
// lavapipe. Other builds loop over the instance's colliders with `type` ANY_TYPE.
#ifdef COLLIDER_RUNS
#define RUN_AT(r, start, EACH) \
    for (uint i_ = 0u; i_ < RUN_LENGTH(r); i_++) { EACH(range_.x + (start) + i_, RUN_TYPE(r)) }
#if COLLIDER_RUNS > 2
#define RUN_2(EACH) RUN_AT(2u, RUN_LENGTH(0u) + RUN_LENGTH(1u), EACH)
#else
#define RUN_2(EACH)
#endif
#if COLLIDER_RUNS > 3
#define RUN_3(EACH) RUN_AT(3u, RUN_LENGTH(0u) + RUN_LENGTH(1u) + RUN_LENGTH(2u), EACH)
#else
#define RUN_3(EACH)
#endif
#define FOR_EACH_COLLIDER(p, EACH) { \
    uvec2 range_ = collider_range(p); \
    RUN_AT(0u, 0u, EACH) RUN_AT(1u, RUN_LENGTH(0u), EACH) RUN_2(EACH) RUN_3(EACH) }
#else
#define FOR_EACH_COLLIDER(p, EACH) { \
    uvec2 range_ = collider_range(p); \
    for (uint k_ = range_.x; k_ < range_.y; k_++) { EACH(k_, ANY_TYPE) } }
#endif

// Runs EACH(k) for every funnel k of particle p's instance, in order: in a build with
// COLLIDER_RUNS, a loop over the funnels alone; in others over every collider, EACH under a test
// of its type (run for each collider, under a mask, on lavapipe).
#ifdef COLLIDER_RUNS
#define FUNNEL_RUN(r) (RUN_TYPE(r) == CVK_COLLIDER_FUNNEL_ID ? RUN_LENGTH(r) : 0u)
const uint FUNNELS = FUNNEL_RUN(0u) + FUNNEL_RUN(1u) + FUNNEL_RUN(2u) + FUNNEL_RUN(3u);
// The place in its instance of the i-th funnel.
uint funnel_at(uint i)
{
    uint start = 0u, at = 0u;
    for (uint r = 0u; r < CVK_COLLIDER_RUNS; r++) {
        uint n = RUN_LENGTH(r);
        if (RUN_TYPE(r) == CVK_COLLIDER_FUNNEL_ID) {
            at = i < n ? start + i : at;
            i = i < n ? 0xffff0000u : i - n;
        }
        start += n;
    }
    return at;
}
#define FOR_EACH_FUNNEL(p, EACH) { \
    uvec2 range_ = collider_range(p); \
    for (uint i_ = 0u; i_ < FUNNELS; i_++) { EACH(range_.x + funnel_at(i_)) } }
#else
#define FOR_EACH_FUNNEL(p, EACH) { \
    uvec2 range_ = collider_range(p); \
    for (uint k_ = range_.x; k_ < range_.y; k_++) { \
        if (collider_shape(k_).type == CVK_COLLIDER_FUNNEL_ID) { EACH(k_) } } }
#endif

// Contact with collider k (of `type`) for a point that starts the substep at x0 and would end
// it at x0 + u, kept r off its surface: returns the corrected displacement.
vec3 collide_shape(uint k, uint type, vec3 x0, vec3 u, float r)
{
    cvk_gpu_collider c = typed_shape(k, type);
    cvk_gpu_pose pose = collider_pose(k);
    vec3 l0, l1;
    local_path(pose, x0, u, l0, l1);
    vec3 hit, n;
    bool touch;
    if (COLLIDER_TYPE_BITS == (1u << CVK_COLLIDER_PLANE_ID) || c.type == CVK_COLLIDER_PLANE_ID) {
        // a half-space: the projection needs no trace
        n = c.b.xyz;
        hit = l1 + (r - dot(n, l1 - c.a.xyz)) * n;
        touch = dot(n, l1 - c.a.xyz) < r;
    } else {
        touch = trace_segment(c, l0, l1, r, hit, n);
    }
    if (!touch)
        return u;
    float depth = dot(n, hit - l1);
    if (depth <= 0.0)
        return u;
    l1 += depth * n;
    l1 = apply_friction(l0, l1, n, depth, c.friction, c.static_friction);
    if (c.type != CVK_COLLIDER_PLANE_ID) {
        // The tangent plane at the touch is exact for flat faces; at edges, corners and
        // curved or sampled surfaces the end may still be within r: push it out along
        // the field's gradient.
        for (int i = 0; i < 2; i++) {
            float left = r - shape_distance(c, l1);
            if (left > 0.0)
                l1 += left * shape_normal(c, l1);
        }
    }
    return quat_rotate(pose.rotation1, l1) + pose.translation1.xyz - x0;
}

// Signed distance from x to collider k (of `type`: typed_shape) as posed at the start (pose 0)
// or end (1) of the substep.
float posed_distance(uint k, uint type, vec3 x, uint pose)
{
    cvk_gpu_pose p = collider_pose(k);
    vec3 l = pose == 0u ? quat_rotate_inverse(p.rotation0, x - p.translation0.xyz)
                        : quat_rotate_inverse(p.rotation1, x - p.translation1.xyz);
    return shape_distance(typed_shape(k, type), l);
}

// The least distance from x to a collider of particle p's instance (a funnel's unsigned), at
// the end of the substep or, with `both`, at its start too (the bounds' collider rules:
// lib/contact/collide.h). Each collider's own type's code alone in a build for runs
// (FOR_EACH_COLLIDER): the decision's check measures it twice a particle at every substep
// (contact_check.comp, built for runs as pd_contact.comp is), the 40 x 40 contact drape's
// about a fifth cheaper on one lavapipe core.
float nearest_solid(uint p, vec3 x, bool both)
{
    float d = 3.0e38;
#define NEAREST_OF(k, type)                               \
    d = min(d, posed_distance(k, type, x, 1u));           \
    if (both)                                             \
        d = min(d, posed_distance(k, type, x, 0u));
    FOR_EACH_COLLIDER(p, NEAREST_OF)
#undef NEAREST_OF
    return d;
}

// Collider contact for particle p that starts the substep at x0 and would end it at x0 + u:
// returns the displacement that keeps it out of every collider of its instance.
vec3 collide_colliders(uint p, vec3 x0, vec3 u)
{
#define COLLIDE_WITH(k, type) u = collide_shape(k, type, x0, u, contact_u.thickness);
    FOR_EACH_COLLIDER(p, COLLIDE_WITH)
#undef COLLIDE_WITH
    return u;
}

// ---- cloth against cloth -------------------------------------------------------------------

// A triangle's centroid, and the farthest its corners are from it: every point of the triangle
// lies within that of its centroid (the faces' hash: contact_edges.comp, contact_detect.comp).
vec3 triangle_centroid(vec3 a, vec3 b, vec3 c)
{
    return (a + b + c) * (1.0 / 3.0);
}

float corner_reach(vec3 a, vec3 b, vec3 c, vec3 g)
{
    return sqrt(max(max(dot(a - g, a - g), dot(b - g, b - g)), dot(c - g, c - g)));
}

// The point of triangle (a, b, c) nearest p and its barycentric weights (Ericson 2005, 5.1.5).
vec3 closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c, out vec3 w)
{
    vec3 ab = b - a, ac = c - a, ap = p - a;
    float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) { w = vec3(1, 0, 0); return a; }
    vec3 bp = p - b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { w = vec3(0, 1, 0); return b; }
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        float v = d1 / (d1 - d3);
        w = vec3(1.0 - v, v, 0.0);
        return a + v * ab;
    }
    vec3 cp = p - c;
    float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) { w = vec3(0, 0, 1); return c; }
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        float v = d2 / (d2 - d6);
        w = vec3(1.0 - v, 0.0, v);
        return a + v * ac;
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        float v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        w = vec3(0.0, 1.0 - v, v);
        return b + v * (c - b);
    }
    float denom = 1.0 / (va + vb + vc);
    float v = vb * denom, t = vc * denom;
    w = vec3(1.0 - v - t, v, t);
    return a + v * ab + t * ac;
}

// The nearest points c1 = p1 + s (q1 - p1) and c2 = p2 + t (q2 - p2) of two segments
// (Ericson 2005, §5.1.9; s = 0 where the segments are parallel).
void closest_segments(vec3 p1, vec3 q1, vec3 p2, vec3 q2, precise out float s,
                      precise out float t, precise out vec3 c1, precise out vec3 c2)
{
    precise vec3 d1 = q1 - p1, d2 = q2 - p2, r = p2 - p1;
    precise float a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, -r);
    s = 0.0;
    t = 0.0;
    if (a > 0.0 && e > 0.0) {
        precise float b = dot(d1, d2), c = dot(d1, -r);
        precise float denom = a * e - b * b;
        s = denom > 0.0 ? clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
        t = (b * s + f) / e;
        if (t < 0.0) {
            t = 0.0;
            s = clamp(-c / a, 0.0, 1.0);
        } else if (t > 1.0) {
            t = 1.0;
            s = clamp((b - c) / a, 0.0, 1.0);
        }
    } else if (a > 0.0) {
        s = clamp(dot(d1, r) / a, 0.0, 1.0);
    } else if (e > 0.0) {
        t = clamp(dot(d2, -r) / e, 0.0, 1.0);
    }
    c1 = p1 + s * d1;
    c2 = p2 + t * d2;
}

// A feature of a contact list entry (shared/layout.h): its corners (internal indices) and how
// many there are (3 for a face, 2 for an edge, 1 for a vertex).
uint feature_corners(uint entry, out uvec3 v)
{
    uint kind = entry & 3u, f = entry >> 2u;
    if (kind == CVK_FEATURE_FACE) {
        v = contact_triangle(f).xyz;
        return 3u;
    }
    if (kind == CVK_FEATURE_EDGE) {
        v = uvec3(contact_edge(f), 0u);
        return 2u;
    }
    v = uvec3(f, 0u, 0u);
    return 1u;
}

// The point of a feature with `count` corners (a, b, c) nearest x, and the corners' weights
// in it.
vec3 feature_closest(vec3 x, uint count, vec3 a, vec3 b, vec3 c, out vec3 w)
{
    if (count == 3u)
        return closest_on_triangle(x, a, b, c, w);
    if (count == 2u) {
        vec3 ab = b - a;
        float len2 = dot(ab, ab);
        float t = len2 > 0.0 ? clamp(dot(x - a, ab) / len2, 0.0, 1.0) : 0.0;
        w = vec3(1.0 - t, t, 0.0);
        return a + t * ab;
    }
    w = vec3(1.0, 0.0, 0.0);
    return a;
}

