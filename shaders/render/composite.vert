#version 450
#extension GL_GOOGLE_include_directive : require
// Composite pass: one triangle over the whole image; or (FOOTPRINT) the shadow on the ground of
// the occupied box grown by the widest penumbra and the texels the shadow lookup moves off the
// ground (render/occupied.glsl), where the ground's shadow is looked up; or (RECT) the
// rectangle where the cloth pass drew and the ambient occlusion can darken (the occupied box
// grown by the occlusion radius with render.ao, and two pixels).
#include "render/frame.glsl"
#if defined(RECT) || defined(FOOTPRINT)
#include "render/occupied.glsl"
#endif

void main()
{
#if defined(FOOTPRINT)
    float penumbra = frame.soft.w > 0.5 ? frame.soft.y : 2.0;
    gl_Position = footprint_corner((penumbra + 2.0) * frame.shadow.y, gl_VertexIndex);
#elif defined(RECT)
    gl_Position = rect_corner(occupied_rect(frame.ao_size.w > 0.5 ? frame.ao.w : 0.0, 4.0 / frame.ao_size.xy),
                              gl_VertexIndex);
#else
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
#endif
}
