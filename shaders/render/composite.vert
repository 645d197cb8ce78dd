#version 450
#extension GL_GOOGLE_include_directive : require
// Composite pass: one triangle over the whole image, or (RECT) the rectangle where the ground
// can be in a shadow or anything darkened by ambient occlusion (render/occupied.glsl: the
// occupied box grown by the occlusion radius and the widest penumbra, with its shadow on the
// ground, and two pixels).
#include "render/frame.glsl"
#ifdef RECT
#include "render/occupied.glsl"
#endif

void main()
{
#ifdef RECT
    float penumbra = frame.soft.w > 0.5 ? frame.soft.y * frame.shadow.y : 2.0 * frame.shadow.y;
    gl_Position = rect_corner(occupied_rect(max(frame.ao.w, penumbra), true, 4.0 / frame.ao_size.xy), gl_VertexIndex);
#else
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
#endif
}
