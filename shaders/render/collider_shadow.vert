#version 450
#extension GL_GOOGLE_include_directive : require
// Shadow pass for colliders: their depth from the key light, posed like collider.vert, so
// they shadow the cloth, the ground and themselves.
#include "render/frame.glsl"
#include "render/collider_pose.glsl"

layout(location = 0) in vec3 position;

void main()
{
    gl_Position = frame.light_view_proj * vec4(posed_point(position), 1.0);
}
