#version 450
#extension GL_GOOGLE_include_directive : require
// Lit pass, ground: one square on the ground plane around the point under the target, made
// from gl_VertexIndex (a triangle strip of 4), no vertex buffer.
#include "frame.glsl"

layout(location = 0) out vec3 world;

void main()
{
    vec3 up = frame.ground_plane.xyz;
    vec3 t = normalize(cross(up, abs(up.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
    vec3 b = cross(up, t);
    vec2 corner = vec2(float(gl_VertexIndex & 1), float(gl_VertexIndex >> 1)) * 2.0 - 1.0;
    corner *= frame.ground_center.w;
    world = frame.ground_center.xyz + t * corner.x + b * corner.y;
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
