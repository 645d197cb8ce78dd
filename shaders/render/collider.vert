#version 450
#extension GL_GOOGLE_include_directive : require
// Collider pass: a collider's triangles at rest, moved by its pose; lit_cloth.frag shades them
// like the cloth (both lights, the key light's shadow map).
#include "render/frame.glsl"
#include "render/collider_pose.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv; // colliders have no texture (lit_cloth.frag)

void main()
{
    world = posed_point(position);
    world_normal = posed_direction(normal);
    uv = vec2(0.0);
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
