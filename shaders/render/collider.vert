#version 450
#extension GL_GOOGLE_include_directive : require
// Collider pass: a collider's triangles at rest, moved by its pose; lit_cloth.frag (built with
// COLLIDER) shades them like the cloth (both lights, the key light's shadow map), projecting a
// texture from the position and normal in the collider's texture frame (render_colliders.c),
// which the pose carries along.
#include "render/frame.glsl"
#include "render/collider_pose.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 frame_position;
layout(location = 3) in vec3 frame_normal;
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv; // no texture coordinates (lit_cloth.frag)
layout(location = 3) out vec3 texture_point;
layout(location = 4) out vec3 texture_normal;

void main()
{
    world = posed_point(position);
    world_normal = posed_direction(normal);
    uv = vec2(0.0);
    texture_point = frame_position;
    texture_normal = frame_normal;
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
