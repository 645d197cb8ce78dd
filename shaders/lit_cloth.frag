#version 450
#extension GL_GOOGLE_include_directive : require
// Lit pass, cloth. Both faces are drawn; a back face is lit with the flipped normal, so the
// side away from the light is dark and the side towards it lit, whichever way the cloth turns
// (seed 002 lit both faces alike, its §9).
#include "frame.glsl"
#include "lighting.glsl"

layout(push_constant) uniform Material {
    vec4 albedo; // rgb: linear colour of this cloth
} material;

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 world_normal;
layout(location = 0) out vec4 color;

void main()
{
    float len = length(world_normal);
    vec3 n = len > 0.0 ? world_normal / len : normalize(frame.eye.xyz - world);
    if (!gl_FrontFacing)
        n = -n;
    color = vec4(shade(world, n, material.albedo.rgb, 0.12), 1.0);
}
