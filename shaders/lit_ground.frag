#version 450
#extension GL_GOOGLE_include_directive : require
// Lit pass, ground: matte, receives the key light's shadow, and fades into the background
// with distance so its edge never shows.
#include "frame.glsl"
#include "lighting.glsl"

layout(location = 0) in vec3 world;
layout(location = 0) out vec4 color;

void main()
{
    vec3 lit = shade(world, frame.ground_plane.xyz, frame.ground_color.rgb, 0.0);
    float away = distance(world, frame.ground_center.xyz) / frame.ground_center.w;
    color = vec4(mix(lit, frame.background.rgb, smoothstep(0.3, 0.95, away)), 1.0);
}
