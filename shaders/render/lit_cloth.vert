#version 450
#extension GL_GOOGLE_include_directive : require
// Cloth pass: straight from the mesh's vertex buffer; built a second time with TEXTURED, which
// also reads the texture coordinates (a second vertex buffer, lib/render/render_textures.c).
// A cloth with a material thickness is drawn twice, each face moved half of it along the
// normal (the rim's vertices come placed from the mesh pass, with no offset here).
#include "render/frame.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
#ifdef TEXTURED
layout(location = 2) in vec2 texture_coordinates;
#endif
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv;
layout(location = 3) out vec3 shadow_world; // where the shadow is looked up (lit_cloth.frag)

// The slab of lit_cloth.frag's Material block: x: the offset along the normal, m.
layout(push_constant) uniform Material {
    layout(offset = 48) vec4 slab;
} material;

void main()
{
    world = position + material.slab.x * normal;
    world_normal = normal;
    shadow_world = world;
#ifdef TEXTURED
    uv = texture_coordinates;
#else
    uv = vec2(0.0);
#endif
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
