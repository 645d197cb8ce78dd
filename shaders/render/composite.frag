#version 450
#extension GL_GOOGLE_include_directive : require
// Composite pass, one sample per pixel: the ground (matte, fading into the background with
// distance) or the sky behind each pixel, found by intersecting the pixel's ray with the
// ground plane, and over it the cloth pass's samples averaged in linear light — the
// multisample resolve. Only the ground patch under the shadow map (SHADOWED) reads the map:
// the ground and sky elsewhere cost a few instructions, not a multisampled draw.
#include "render/frame.glsl"
#include "render/lighting.glsl"

layout(constant_id = 1) const bool SHADOWED = false;
layout(constant_id = 2) const int SAMPLES = 4;

#ifdef SINGLE_SAMPLE
layout(set = 0, binding = 2) uniform sampler2D cloth;
#else
layout(set = 0, binding = 2) uniform sampler2DMS cloth;
#endif

layout(location = 0) out vec4 color;

// A faint checkerboard, for a sense of scale and distance: the squares' share of the pixel's
// footprint (a box filter of the pattern), so it fades to grey far away instead of
// shimmering.
float checker(vec3 ground)
{
    vec2 uv = vec2(dot(ground, frame.ground_axes[0].xyz), dot(ground, frame.ground_axes[1].xyz));
    vec2 w = fwidth(uv) + 1e-4;
    vec2 i = 2.0 * (abs(fract((uv - 0.5 * w) * 0.5) - 0.5) - abs(fract((uv + 0.5 * w) * 0.5) - 0.5)) / w;
    return 1.0 + 0.035 * i.x * i.y;
}

// The ground is flat and its lights directional, so its colour is two constants: only the
// shadow and the fade vary over it.
vec3 background(vec2 pixel)
{
    vec3 ray = frame.ray_base.xyz + pixel.x * frame.ray_dx.xyz + pixel.y * frame.ray_dy.xyz;
    vec3 up = frame.ground_plane.xyz;
    float toward = dot(ray, up);
    float height = dot(frame.eye.xyz, up) - frame.ground_plane.w;
    // Sky where the ray never meets the ground, or the eye is below it.
    if (frame.fog.z == 0.0 || toward >= 0.0 || height <= 0.0)
        return frame.background.rgb;
    // The ray's component along the view is 1: t is the hit's depth.
    float t = height / -toward;
    vec3 ground = frame.eye.xyz + t * ray;
    vec3 lit = frame.ground_unlit.rgb;
    if (SHADOWED)
        lit += frame.ground_key.rgb * key_visibility(ground, up);
    else
        lit += frame.ground_key.rgb;
    return mix(lit * checker(ground), frame.background.rgb, smoothstep(frame.fog.x, frame.fog.y, t));
}

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    // Samples hold the square root of linear light (lit_cloth.frag): squared, then averaged.
#ifdef SINGLE_SAMPLE
    vec4 over = texelFetch(cloth, pixel, 0);
    over.rgb *= over.rgb;
#else
    vec4 over = vec4(0.0);
    for (int s = 0; s < SAMPLES; s++) {
        vec4 c = texelFetch(cloth, pixel, s);
        over += vec4(c.rgb * c.rgb, c.a);
    }
    over /= float(SAMPLES);
#endif
    // The cloth pass cleared to transparent: `over` is premultiplied by its coverage.
    color = vec4(over.rgb + (1.0 - over.a) * background(gl_FragCoord.xy), 1.0);
}
