#version 450
#extension GL_GOOGLE_include_directive : require
// Composite pass, one sample per pixel: the ground (matte, fading into the background with
// distance) or the sky behind each pixel, found by intersecting the pixel's ray with the
// ground plane, and over it the cloth pass's samples averaged in linear light — the
// multisample resolve. Only the occupied box's shadow on the ground (SHADOWED: composite.vert
// with FOOTPRINT) reads the shadow map: the ground and sky elsewhere cost a few instructions.
#include "render/frame.glsl"
#include "render/lighting.glsl"

// Outside the occupied rectangle (composite.vert), where the cloth pass drew nothing: its
// samples are not read.
layout(constant_id = 0) const bool BARE = false;
layout(constant_id = 1) const bool SHADOWED = false;
layout(constant_id = 2) const int SAMPLES = 4;
// The ambient occlusion pass ran (render.ao): darken by what it found.
layout(constant_id = 3) const bool OCCLUDED = false;
// render.tone_map.
layout(constant_id = 6) const bool TONE_MAP = true;
// The ground has a texture (the plane collider's); else the checkerboard.
layout(constant_id = 8) const bool GROUND_TEXTURED = false;

#ifdef SINGLE_SAMPLE
layout(set = 0, binding = 2) uniform sampler2D cloth;
layout(set = 0, binding = 5) uniform sampler2D scene_depth;
#else
layout(set = 0, binding = 2) uniform sampler2DMS cloth;
layout(set = 0, binding = 5) uniform sampler2DMS scene_depth;
#endif
// The ambient occlusion, blurred (ao_blur.frag): x light left, y depth along the view.
layout(set = 0, binding = 6) uniform sampler2D occlusion_map;
// A textured ground's texture (the plane collider's set).
layout(set = 0, binding = 3) uniform sampler2D ground_map;

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

vec3 ray(vec2 pixel)
{
    return frame.ray_base.xyz + pixel.x * frame.ray_dx.xyz + pixel.y * frame.ray_dy.xyz;
}

// Ambient occlusion at this pixel: the mean of the 2 x 2 texels of the blurred occlusion around
// it whose depth is within 3 % of the pixel's own, so the occlusion of one surface does not
// bleed onto another behind it.
float occlusion(ivec2 pixel)
{
    float d = texelFetch(scene_depth, pixel, 0).r;
    float t;
    if (d > 0.0) {
        t = frame.ao.x / (frame.ao.y * d + frame.ao.z);
    } else {
        vec3 up = frame.ground_plane.xyz;
        float toward = dot(ray(vec2(pixel) + 0.5), up);
        float height = dot(frame.eye.xyz, up) - frame.ground_plane.w;
        if (frame.fog.z == 0.0 || toward >= 0.0 || height <= 0.0)
            return 1.0;
        t = height / -toward;
    }
    vec2 uv = (vec2(pixel) + 0.5) * 0.5 / vec2(textureSize(occlusion_map, 0));
    vec4 light = textureGather(occlusion_map, uv, 0);
    vec4 depth = textureGather(occlusion_map, uv, 1);
    vec4 w = max(1.0 - abs(depth - t) / (0.03 * t), 0.0);
    float sum = dot(w, vec4(1.0));
    return sum > 1e-3 ? dot(light, w) / sum : 1.0;
}

// Where pixel's ray meets the ground (t: its depth along the view, up to the horizon).
vec3 ground_point(vec2 pixel, float height)
{
    float toward = min(dot(ray(pixel), frame.ground_plane.xyz), -1e-6);
    return frame.eye.xyz + height / -toward * ray(pixel);
}

vec2 ground_uv(vec3 p)
{
    return vec2(dot(frame.ground_texture[0].xyz, p) + frame.ground_texture[0].w,
                dot(frame.ground_texture[1].xyz, p) + frame.ground_texture[1].w);
}

// A textured ground's colour at `ground`: its texture, the mip level from where the rays of the
// next pixels meet the ground (no derivatives: the sky's pixels take another branch).
vec3 ground_albedo(vec2 pixel, vec3 ground, float height)
{
    vec2 uv = ground_uv(ground);
    vec2 du = ground_uv(ground_point(pixel + vec2(1.0, 0.0), height)) - uv;
    vec2 dv = ground_uv(ground_point(pixel + vec2(0.0, 1.0), height)) - uv;
    return textureGrad(ground_map, uv, du, dv).rgb;
}

// The ground is flat and its lights directional, so its colour is two constants (times its
// texture's, where it has one): only the shadow and the fade vary over it.
vec3 background(vec2 pixel)
{
    vec3 up = frame.ground_plane.xyz;
    float toward = dot(ray(pixel), up);
    float height = dot(frame.eye.xyz, up) - frame.ground_plane.w;
    // Sky where the ray never meets the ground, or the eye is below it.
    if (frame.fog.z == 0.0 || toward >= 0.0 || height <= 0.0)
        return frame.background.rgb;
    // The ray's component along the view is 1: t is the hit's depth.
    float t = height / -toward;
    vec3 ground = frame.eye.xyz + t * ray(pixel);
    vec3 lit = frame.ground_unlit.rgb;
    if (SHADOWED)
        lit += frame.ground_key.rgb * key_visibility(ground, up);
    else
        lit += frame.ground_key.rgb;
    vec3 albedo = GROUND_TEXTURED ? ground_albedo(pixel, ground, height) : vec3(checker(ground));
    return mix(lit * albedo, frame.background.rgb, smoothstep(frame.fog.x, frame.fog.y, t));
}

void main()
{
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    // Samples hold the square root of half the linear light (lit_cloth.frag): squared and
    // doubled, then averaged.
    vec4 over = vec4(0.0);
    if (!BARE) {
#ifdef SINGLE_SAMPLE
        over = texelFetch(cloth, pixel, 0);
        over.rgb *= 2.0 * over.rgb;
#else
        for (int s = 0; s < SAMPLES; s++) {
            vec4 c = texelFetch(cloth, pixel, s);
            over += vec4(2.0 * c.rgb * c.rgb, c.a);
        }
        over /= float(SAMPLES);
#endif
    }
    // The cloth pass cleared to transparent: `over` is premultiplied by its coverage.
    color = vec4(over.rgb + (1.0 - over.a) * background(gl_FragCoord.xy), 1.0);
    if (OCCLUDED)
        color.rgb *= occlusion(pixel);
    // Highlights rolled off (a film's shoulder): unchanged up to the knee, then approaching 1
    // smoothly (same value and slope at the knee), so light past white keeps its shading
    // instead of clipping flat. The sky and most surfaces lie below the knee.
    if (TONE_MAP) {
        const float knee = 0.6, room = 1.0 - knee;
        vec3 over_knee = max(color.rgb - knee, 0.0);
        color.rgb = min(color.rgb, vec3(knee)) + room * (1.0 - exp(-over_knee / room));
    }
}
