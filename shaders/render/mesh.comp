#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/layout.h"
// Mesh generation (seed 002 §5.4.1) in one dispatch over max(vertices, triangles, rim edges):
// - triangle t is drawn where the springs along its edges are alive; a torn one becomes three
//   equal indices, so the index count, and every draw call, stays the same;
// - vertex v (user order: cloth by cloth, row-major) takes its particle's position and the
//   area-weighted average of its live triangles' normals: the plain sum of their cross
//   products, whose length is twice the area. Each vertex gathers its own triangles from a
//   fixed slot order: no atomics, the same bits on every run.
// - rim edge k (cloths with a material thickness: an edge that is, or may become, a border)
//   becomes the quad that joins the slab's two faces along it, the vertices half the thickness
//   off the middle along the smooth normals, as lit_cloth.vert moves the faces, wound so its
//   front faces away from its one live triangle; a point while the edge has two live triangles
//   or none.
// An edge without a spring (a constraint type the scene leaves out) never tears.

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint MAX_ADJACENT = 6;

const uint NONE = 0xffffffffu;

layout(set = 0, binding = 0) uniform samplerBuffer positions;          // xyz, internal order
layout(set = 0, binding = 1) uniform usamplerBuffer spring_alive;      // per spring: 1, 0 torn
layout(set = 0, binding = 2) uniform usamplerBuffer triangle_vertices; // xyz: vertices (user order)
layout(set = 0, binding = 3) uniform usamplerBuffer triangle_particles;// xyz: the same, internal
layout(set = 0, binding = 4) uniform usamplerBuffer triangle_springs;  // xyz: spring per edge or NONE
layout(set = 0, binding = 5) uniform usamplerBuffer particle_of;       // vertex -> internal index
layout(set = 0, binding = 6) uniform usamplerBuffer vertex_triangles;  // slot-major, NONE padded
layout(std430, set = 0, binding = 7) writeonly buffer Vertices { vec4 vertices[]; }; // position, normal
layout(std430, set = 0, binding = 8) writeonly buffer Indices { uint indices[]; };
layout(set = 0, binding = 9) uniform usamplerBuffer rim_edges;         // triangles, slot, half thickness
layout(std430, set = 0, binding = 10) writeonly buffer RimVertices { vec4 rim_vertices[]; };

// The push constants: cvk_mesh_push, declared with the C side in shared/layout.h.
CVK_DECLARE_PUSH(CVK_MESH_PUSH_FIELDS)

bool spring_intact(uint s)
{
    return s == NONE || texelFetch(spring_alive, int(s)).x != 0u;
}

bool triangle_alive(uint t)
{
    uvec3 s = texelFetch(triangle_springs, int(t)).xyz;
    return spring_intact(s.x) && spring_intact(s.y) && spring_intact(s.z);
}

vec3 position(uint particle)
{
    return texelFetch(positions, int(particle)).xyz;
}

void write_triangle(uint t)
{
    uvec3 v = texelFetch(triangle_vertices, int(t)).xyz;
    if (!triangle_alive(t))
        v = v.xxx;
    indices[3u * t] = v.x;
    indices[3u * t + 1u] = v.y;
    indices[3u * t + 2u] = v.z;
}

vec3 face_normal(uint t)
{
    uvec3 p = texelFetch(triangle_particles, int(t)).xyz;
    vec3 a = position(p.x);
    return cross(position(p.y) - a, position(p.z) - a);
}

vec3 smooth_normal(uint v)
{
    vec3 normal = vec3(0.0);
    for (uint slot = 0u; slot < MAX_ADJACENT; slot++) {
        uint t = texelFetch(vertex_triangles, int(slot * pc.vertex_count + v)).x;
        if (t == NONE || !triangle_alive(t))
            continue;
        normal += face_normal(t);
    }
    float len = length(normal);
    return len > 0.0 ? normal / len : vec3(0.0);
}

void write_vertex(uint v)
{
    vertices[2u * v] = vec4(position(texelFetch(particle_of, int(v)).x), 1.0);
    vertices[2u * v + 1u] = vec4(smooth_normal(v), 0.0);
}

void write_rim(uint k)
{
    uvec4 e = texelFetch(rim_edges, int(k));
    uvec3 v = texelFetch(triangle_vertices, int(e.x)).xyz;
    uvec3 p = texelFetch(triangle_particles, int(e.x)).xyz;
    uint next = e.z == 2u ? 0u : e.z + 1u;
    // a to b is the edge's direction in its first triangle, b to a in the second
    uint a = v[e.z], b = v[next];
    vec3 pa = position(p[e.z]), pb = position(p[next]);
    bool first = triangle_alive(e.x);
    bool second = e.y != NONE && triangle_alive(e.y);
    vec4 corners[4] = vec4[4](vec4(pa, 1.0), vec4(pa, 1.0), vec4(pa, 1.0), vec4(pa, 1.0));
    vec3 outward = vec3(0.0);
    if (first != second) {
        if (second) {
            uint swap_vertex = a;
            a = b;
            b = swap_vertex;
            vec3 swap_point = pa;
            pa = pb;
            pb = swap_point;
        }
        vec3 across = cross(pb - pa, face_normal(first ? e.x : e.y));
        float len = length(across);
        outward = len > 0.0 ? across / len : vec3(0.0);
        float half_thickness = uintBitsToFloat(e.w);
        vec3 na = half_thickness * smooth_normal(a), nb = half_thickness * smooth_normal(b);
        // wound so that the front faces outward: (pa−, pb−, pb+) turns about `outward`
        corners = vec4[4](vec4(pa - na, 1.0), vec4(pb - nb, 1.0), vec4(pb + nb, 1.0), vec4(pa + na, 1.0));
    }
    for (uint i = 0u; i < 4u; i++) {
        rim_vertices[2u * (4u * k + i)] = corners[i];
        rim_vertices[2u * (4u * k + i) + 1u] = vec4(outward, 0.0);
    }
}

void main()
{
    uint count = max(max(pc.vertex_count, pc.triangle_count), pc.rim_edge_count);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint k = gl_GlobalInvocationID.x; k < count; k += stride) {
        if (k < pc.triangle_count)
            write_triangle(k);
        if (k < pc.vertex_count)
            write_vertex(k);
        if (k < pc.rim_edge_count)
            write_rim(k);
    }
}
