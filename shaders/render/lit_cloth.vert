#version 450
#extension GL_GOOGLE_include_directive : require
// Cloth pass: straight from the mesh's vertex buffer; built a second time with TEXTURED, which
// also reads the texture coordinates (a second vertex buffer, lib/render/render_textures.c).
#include "render/frame.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
#ifdef TEXTURED
layout(location = 2) in vec2 texture_coordinates;
#endif
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv;

void main()
{
    world = position;
    world_normal = normal;
#ifdef TEXTURED
    uv = texture_coordinates;
#else
    uv = vec2(0.0);
#endif
    gl_Position = frame.view_proj * vec4(position, 1.0);
}
