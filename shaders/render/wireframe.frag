#version 450
#extension GL_GOOGLE_include_directive : require
// Wireframe pass (render.wireframe): the cloth's triangles drawn as lines over its shading, in
// a dark shade of the cloth's own colour, so the structure reads on any colour. The pipeline
// draws after the cloth with a depth bias towards the eye: an edge wins the depth test against
// its own triangles (no z-fighting) and still loses against cloth in front of it.
#include "render/frame.glsl"

layout(constant_id = 0) const bool CLIP_BELOW_GROUND = true;

layout(push_constant) uniform Material {
    vec4 albedo; // rgb: linear colour of this cloth
} material;

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 world_normal; // written by lit_cloth.vert; not needed for a line
layout(location = 2) in vec2 uv;           // the same
layout(location = 3) in vec3 shadow_world; // the same
layout(location = 0) out vec4 color;

void main()
{
    if (CLIP_BELOW_GROUND && dot(world, frame.ground_plane.xyz) < frame.ground_plane.w)
        discard;
    // The square root of linear light, as the cloth pass stores it (see lit_cloth.frag).
    color = vec4(sqrt(0.03 * material.albedo.rgb), 1.0); // 0.06 of the colour, as lit_cloth.frag stores it
}
