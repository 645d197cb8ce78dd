#version 450
#extension GL_GOOGLE_include_directive : require
// Cloth pass: straight from the mesh's vertex buffer; built a second time with TEXTURED, which
// also reads the texture coordinates (a second vertex buffer, lib/render/render_textures.c).
// A cloth with a material thickness is drawn twice, each face moved half of it along the
// normal (the rim's vertices come placed from the mesh pass, with no offset here).
// Built with VERTEX_LIGHT for cloths whose triangles are a few pixels across (render.vertex_lighting):
// the light is found here, at the vertices, for both faces, and lit_cloth.frag (built with it
// too) only puts the albedo in: a triangle that small shows no difference, and a CPU device shades
// every triangle's whole blocks of pixels, many times the cloth's own pixels.
#include "render/frame.glsl"
#ifdef VERTEX_LIGHT
#include "render/lighting.glsl"
#endif

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
#ifdef TEXTURED
layout(location = 2) in vec2 texture_coordinates;
#endif
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv;
layout(location = 3) out vec3 shadow_world; // where the shadow is looked up (lit_cloth.frag)
#ifdef VERTEX_LIGHT
// fabric_terms() of the front face (the side the normal points to) and of the back face: the
// colour is albedo · d + sheen · s
layout(location = 4) out vec3 front_d;
layout(location = 5) out vec3 front_s;
layout(location = 6) out vec3 back_d;
layout(location = 7) out vec3 back_s;
#endif

// lit_cloth.frag's Material block from its fabric: y: the sheen's roughness; slab: x: the
// offset along the normal, m; y: the thickness.
layout(push_constant) uniform Material {
    layout(offset = 32) vec4 fabric;
    vec4 slab;
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
#ifdef VERTEX_LIGHT
    // As lit_cloth.frag does for each face: the key light's shadow on the side it falls on,
    // through a thick cloth's slab to its other face.
    float len = length(normal);
    vec3 n = len > 0.0 ? normal / len : normalize(frame.eye.xyz - world);
    bool towards = dot(n, frame.key_direction.xyz) > 0.0;
    vec3 lit_side = towards ? n : -n;
    float through = material.slab.y;
    float front = key_visibility(towards ? world : world - n * through, lit_side);
    float back = through > 0.0 ? key_visibility(towards ? world + n * through : world, lit_side) : front;
    fabric_terms(world, n, material.fabric.y, front, front_d, front_s);
    fabric_terms(world, -n, material.fabric.y, back, back_d, back_s);
#endif
}
