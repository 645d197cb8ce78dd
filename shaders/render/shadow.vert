#version 450
#extension GL_GOOGLE_include_directive : require
// Shadow pass: the cloth's depth as the key light sees it. Both faces cast; there is no
// fragment shader, and slope-scaled depth bias (pipeline state) keeps lit faces out of their
// own shadow. A thick cloth casts its slab: each face moved as lit_cloth.vert moves it, and the
// rim.
#include "render/frame.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;

layout(push_constant) uniform Material {
    layout(offset = 48) vec4 slab; // x: the offset along the normal, m
} material;

void main()
{
    gl_Position = frame.light_view_proj * vec4(position + material.slab.x * normal, 1.0);
}
