#version 450
#extension GL_GOOGLE_include_directive : require
// Composite pass: one triangle over the whole image, or (PATCH) the quad of ground under the
// shadow map, the only ground a shadow can fall on.
#include "render/frame.glsl"

layout(constant_id = 0) const bool PATCH = false;

void main()
{
    if (PATCH) {
        gl_Position = frame.view_proj * vec4(frame.patch_corners[gl_VertexIndex].xyz, 1.0);
    } else {
        vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
        gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
    }
}
