#version 450
#extension GL_GOOGLE_include_directive : require
// Cloth pass: straight from the mesh's vertex buffer.
#include "frame.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;

void main()
{
    world = position;
    world_normal = normal;
    gl_Position = frame.view_proj * vec4(position, 1.0);
}
