#version 450
#extension GL_GOOGLE_include_directive : require
// Ambient occlusion blur: each texel of the occlusion (ao.frag) becomes the mean of the 4 x 4
// texels around it whose depth along the view is within 5 % of its own: the four turns of the
// pass's 2 x 2 pattern and the few taps' noise blend into a smooth result, and the occlusion of
// one surface does not bleed onto another behind it. Texels with no depth (the sky) stay open.
#include "render/frame.glsl"

layout(set = 0, binding = 9) uniform sampler2D occlusion_raw; // x: light left, y: depth (0: none)

layout(location = 0) out vec2 result;

void main()
{
    ivec2 q = ivec2(gl_FragCoord.xy);
    float t = texelFetch(occlusion_raw, q, 0).y;
    if (t == 0.0) {
        result = vec2(1.0, 0.0);
        return;
    }
    vec2 inv = 1.0 / vec2(textureSize(occlusion_raw, 0));
    float sum = 0.0, weight = 0.0;
    for (int k = 0; k < 4; k++) {
        // the 2 x 2 texels whose corner is at (q - 1 or q + 1) + 0.5 ... gathered about the
        // texel corners q + (-1, -1), (1, -1), (-1, 1), (1, 1): texels q - 2 .. q + 1
        vec2 corner = vec2(q) + vec2(k & 1, k >> 1) * 2.0 - 1.0;
        vec4 light = textureGather(occlusion_raw, corner * inv, 0);
        vec4 depth = textureGather(occlusion_raw, corner * inv, 1);
        vec4 w = vec4(greaterThan(depth, vec4(0.0))) * max(1.0 - abs(depth - t) / (0.05 * t), 0.0);
        sum += dot(light, w);
        weight += dot(w, vec4(1.0));
    }
    result = vec2(weight > 1e-3 ? sum / weight : 1.0, t);
}
