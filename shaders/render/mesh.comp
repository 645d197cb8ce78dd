#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/layout.h"
// Mesh generation (seed 002 §5.4.1) in one dispatch over max(vertices, triangles, rim edges):
// - triangle t is drawn where the springs along its edges are alive; a torn one becomes three
//   equal indices, so the index count, and every draw call, stays the same;
// - a quad split along a diagonal whose spring is torn while the spring along its other
//   diagonal holds (a grid's cell, a mesh file's quad, on a tearing cloth) is drawn split
//   along that other diagonal: its two triangles take their rows from the tables' second half
//   (lib/render/mesh.c, make_other_splits), so a cut running across the split diagonals
//   follows the diagonals the cloth still holds instead of stepping around whole cells;
// - vertex v (user order: cloth by cloth, row-major) takes its particle's position and the
//   area-weighted average of its live triangles' normals: the plain sum of their cross
//   products, whose length is twice the area. Each vertex gathers its own triangles from a
//   fixed slot order: no atomics, the same bits on every run.
// - rim edge k (cloths with a material thickness: an edge that is, or may become, a border)
//   becomes the quad that joins the slab's two faces along it, the vertices half the thickness
//   off the middle along the smooth normals, as lit_cloth.vert moves the faces, wound so its
//   front faces away from its one live triangle; a point while the edge has two live triangles
//   or none (its table row names the triangles that may hold it, in either split).
// An edge without a spring (a constraint type the scene leaves out) never tears.

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint MAX_ADJACENT = 6;
// Some spring may tear. Without tearing every triangle lives, is drawn from its own row and every
// vertex is held: the springs are never read (a CPU device would run the border search for every
// vertex however its branches go).
layout(constant_id = 2) const bool TEARING = true;

const uint NONE = 0xffffffffu;

layout(set = 0, binding = 0) uniform samplerBuffer positions;          // xyz, internal order
layout(set = 0, binding = 1) uniform usamplerBuffer spring_alive;      // per spring: 1, 0 torn
// The triangle tables: 2 · triangle_count rows, row t the triangle, row triangle_count + t
// the triangle drawn in its place in its quad's other split; row t's w: the split diagonal's
// spring (triangle_vertices) and the other diagonal's (triangle_springs), or NONE.
layout(set = 0, binding = 2) uniform usamplerBuffer triangle_vertices; // xyz: vertices (user order)
layout(set = 0, binding = 3) uniform usamplerBuffer triangle_particles;// xyz: the same, internal
layout(set = 0, binding = 4) uniform usamplerBuffer triangle_springs;  // xyz: spring per edge or NONE
layout(set = 0, binding = 5) uniform usamplerBuffer particle_of;       // vertex -> internal index,
                                                                       // | CVK_MESH_HELD: never smoothed
layout(set = 0, binding = 6) uniform usamplerBuffer vertex_triangles;  // slot-major, NONE padded
layout(std430, set = 0, binding = 7) writeonly buffer Vertices { vec4 vertices[]; }; // position, normal
layout(std430, set = 0, binding = 8) writeonly buffer Indices { uint indices[]; };
layout(set = 0, binding = 9) uniform usamplerBuffer rim_edges;         // 2 per edge: (a, b, half thickness),
                                                                       // the triangles that may hold it
layout(std430, set = 0, binding = 10) writeonly buffer RimVertices { vec4 rim_vertices[]; };

// The push constants: cvk_mesh_push, declared with the C side in shared/layout.h.
CVK_DECLARE_PUSH(CVK_MESH_PUSH_FIELDS)

bool spring_intact(uint s)
{
    return s == NONE || texelFetch(spring_alive, int(s)).x != 0u;
}

// Whether the triangle of table row r is alive: the springs along its edges hold.
bool triangle_alive(uint r)
{
    if (!TEARING)
        return true;
    uvec3 s = texelFetch(triangle_springs, int(r)).xyz;
    return spring_intact(s.x) && spring_intact(s.y) && spring_intact(s.z);
}

// The row triangle t is drawn from: its own, or its other split's while its quad's split
// diagonal is torn and the other diagonal holds.
uint drawn_row(uint t)
{
    if (!TEARING)
        return t;
    uint other = texelFetch(triangle_springs, int(t)).w;
    if (other == NONE)
        return t;
    uint split = texelFetch(triangle_vertices, int(t)).w;
    return !spring_intact(split) && spring_intact(other) ? pc.triangle_count + t : t;
}

vec3 position(uint particle)
{
    return texelFetch(positions, int(particle)).xyz;
}

void write_triangle(uint t)
{
    uint r = drawn_row(t);
    uvec3 v = texelFetch(triangle_vertices, int(r)).xyz;
    if (!triangle_alive(r))
        v = v.xxx;
    indices[3u * t] = v.x;
    indices[3u * t + 1u] = v.y;
    indices[3u * t + 2u] = v.z;
}

vec3 face_normal(uint r)
{
    uvec3 p = texelFetch(triangle_particles, int(r)).xyz;
    vec3 a = position(p.x);
    return cross(position(p.y) - a, position(p.z) - a);
}

// Vertex v as drawn: its smooth normal, the area-weighted average of its live triangles'
// normals, and where it is drawn: at its particle, or, on a torn border and not held, halfway
// from its particle to the midpoint of its two neighbours along the border. A cut that steps
// or zig-zags from vertex to vertex (the springs break along the grid) is drawn as the line
// through its steps' middles: one pass of Laplacian smoothing along the border with weight
// 1/2, which takes a period-two zig-zag or staircase to a straight line. Only the picture
// moves; the particles do not. The border: the triangles are wound alike, so an edge v − x
// that two live triangles share is the one's edge out of v and the other's edge into v; an
// edge out of v that is no triangle's edge in (and the reverse) lies on one triangle only.
// v is on a torn border when it has exactly one such edge each way. The arrays are indexed
// by slot, a loop of fixed length, so they stay in registers.
void gather_vertex(uint v, out vec3 normal, out vec3 drawn)
{
    uint entry = texelFetch(particle_of, int(v)).x;
    vec3 p = position(entry & ~CVK_MESH_HELD);
    uint next[MAX_ADJACENT];
    uint prev[MAX_ADJACENT];
    vec3 sum = vec3(0.0);
    for (uint slot = 0u; slot < MAX_ADJACENT; slot++) {
        next[slot] = NONE;
        prev[slot] = NONE;
        uint t = texelFetch(vertex_triangles, int(slot * pc.vertex_count + v)).x;
        if (t == NONE)
            continue;
        uint r = drawn_row(t);
        uvec3 c = texelFetch(triangle_vertices, int(r)).xyz;
        if (!(c.x == v || c.y == v || c.z == v) || !triangle_alive(r))
            continue;
        sum += face_normal(r);
        next[slot] = c.x == v ? c.y : c.y == v ? c.z : c.x;
        prev[slot] = c.x == v ? c.z : c.y == v ? c.x : c.y;
    }
    float len = length(sum);
    normal = len > 0.0 ? sum / len : vec3(0.0);
    drawn = p;
    if (!TEARING || (entry & CVK_MESH_HELD) != 0u)
        return;
    uint outs = 0u, ins = 0u, out_end = NONE, in_end = NONE;
    for (uint i = 0u; i < MAX_ADJACENT; i++) {
        bool out_shared = false, in_shared = false;
        for (uint j = 0u; j < MAX_ADJACENT; j++) {
            out_shared = out_shared || prev[j] == next[i];
            in_shared = in_shared || next[j] == prev[i];
        }
        if (next[i] != NONE && !out_shared) {
            outs++;
            out_end = next[i];
        }
        if (prev[i] != NONE && !in_shared) {
            ins++;
            in_end = prev[i];
        }
    }
    if (outs != 1u || ins != 1u)
        return;
    vec3 a = position(texelFetch(particle_of, int(out_end)).x & ~CVK_MESH_HELD);
    vec3 b = position(texelFetch(particle_of, int(in_end)).x & ~CVK_MESH_HELD);
    drawn = 0.5 * p + 0.25 * (a + b);
}

void write_vertex(uint v)
{
    vec3 normal, drawn;
    gather_vertex(v, normal, drawn);
    vertices[2u * v] = vec4(drawn, 1.0);
    vertices[2u * v + 1u] = vec4(normal, 0.0);
}

void write_rim(uint k)
{
    uvec4 e = texelFetch(rim_edges, int(2u * k));
    uvec4 candidates = texelFetch(rim_edges, int(2u * k + 1u));
    uint a = e.x, b = e.y;
    // the live triangles that hold the edge, and the first one's direction along it
    uint lives = 0u, live = NONE;
    bool along = true;
    for (uint i = 0u; i < 4u; i++) {
        if (candidates[i] == NONE)
            continue;
        uint r = drawn_row(candidates[i]);
        uvec3 v = texelFetch(triangle_vertices, int(r)).xyz;
        if (!triangle_alive(r) || !any(equal(v, uvec3(a))) || !any(equal(v, uvec3(b))))
            continue;
        if (lives++ == 0u) {
            live = r;
            along = v.x == a ? v.y == b : v.y == a ? v.z == b : v.x == b;
        }
    }
    vec3 pa = position(texelFetch(particle_of, int(a)).x & ~CVK_MESH_HELD);
    vec4 corners[4] = vec4[4](vec4(pa, 1.0), vec4(pa, 1.0), vec4(pa, 1.0), vec4(pa, 1.0));
    vec3 outward = vec3(0.0);
    if (lives == 1u) {
        if (!along) {
            uint swap_vertex = a;
            a = b;
            b = swap_vertex;
        }
        // a to b is the edge's direction in its live triangle
        vec3 na, nb, pb;
        gather_vertex(a, na, pa);
        gather_vertex(b, nb, pb);
        vec3 across = cross(pb - pa, face_normal(live));
        float len = length(across);
        outward = len > 0.0 ? across / len : vec3(0.0);
        float half_thickness = uintBitsToFloat(e.z);
        na *= half_thickness;
        nb *= half_thickness;
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
