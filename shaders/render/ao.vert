#version 450
#extension GL_GOOGLE_include_directive : require
// Ambient occlusion pass: the rectangle of the image where something can darken something
// (render/occupied.glsl: the occupied box grown by the radius, and two of the pass's texels);
// the pass clears the rest to open (no occlusion).
#include "render/frame.glsl"
#include "render/occupied.glsl"

void main()
{
    vec2 texel = 2.0 / ceil(0.5 * frame.ao_size.xy);
    gl_Position = rect_corner(occupied_rect(frame.ao.w, 2.0 * texel), gl_VertexIndex);
}
