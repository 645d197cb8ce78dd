#version 450
#extension GL_GOOGLE_include_directive : require
// Cloth pass: lit and shadowed cloth over a transparent background, multisampled; the
// composite pass puts it over the ground and sky. The colliders (collider.vert) are shaded
// here too, with their own colour. Both faces are drawn; a back face is lit
// with the flipped normal, so the side away from the light is dark and the side towards it
// lit, whichever way the cloth turns (seed 002 lit both faces alike, its §9).
#include "frame.glsl"
#include "lighting.glsl"

// The ground hides what is below it (a cloth without a collider falls through).
layout(constant_id = 0) const bool CLIP_BELOW_GROUND = true;

layout(push_constant) uniform Material {
    vec4 albedo; // rgb: linear colour of this cloth
} material;

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 world_normal;
layout(location = 0) out vec4 color;

void main()
{
    if (CLIP_BELOW_GROUND && dot(world, frame.ground_plane.xyz) < frame.ground_plane.w)
        discard;
    float len = length(world_normal);
    vec3 n = len > 0.0 ? world_normal / len : normalize(frame.eye.xyz - world);
    if (!gl_FrontFacing)
        n = -n;
    float visible = dot(n, frame.key_direction.xyz) > 0.0 ? key_visibility(world, n) : 0.0;
    // Stored as the square root of linear light: the composite pass squares it back before
    // averaging the samples, and 8 bits of it are about as fine in the dark as sRGB.
    color = vec4(sqrt(clamp(shade(world, n, material.albedo.rgb, 0.12, visible), 0.0, 1.0)), 1.0);
}
