#version 450
#extension GL_GOOGLE_include_directive : require
#include "shared/layout.h"
// Mesh generation (seed 002 §5.4.1) in one dispatch over max(vertices, triangles):
// - triangle t is drawn where the springs along its edges are alive; a torn one becomes three
//   equal indices, so the index count, and every draw call, stays the same;
// - vertex v (user order: cloth by cloth, row-major) takes its particle's position and the
//   area-weighted average of its live triangles' normals: the plain sum of their cross
//   products, whose length is twice the area. Each vertex gathers its own triangles from a
//   fixed slot order: no atomics, the same bits on every run.
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

void write_vertex(uint v)
{
    vec3 normal = vec3(0.0);
    for (uint slot = 0u; slot < MAX_ADJACENT; slot++) {
        uint t = texelFetch(vertex_triangles, int(slot * pc.vertex_count + v)).x;
        if (t == NONE || !triangle_alive(t))
            continue;
        uvec3 p = texelFetch(triangle_particles, int(t)).xyz;
        vec3 a = position(p.x);
        normal += cross(position(p.y) - a, position(p.z) - a);
    }
    float len = length(normal);
    vertices[2u * v] = vec4(position(texelFetch(particle_of, int(v)).x), 1.0);
    vertices[2u * v + 1u] = vec4(len > 0.0 ? normal / len : vec3(0.0), 0.0);
}

void main()
{
    uint count = max(pc.vertex_count, pc.triangle_count);
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint k = gl_GlobalInvocationID.x; k < count; k += stride) {
        if (k < pc.triangle_count)
            write_triangle(k);
        if (k < pc.vertex_count)
            write_vertex(k);
    }
}
