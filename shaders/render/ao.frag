#version 450
#extension GL_GOOGLE_include_directive : require
// Ambient occlusion pass, at half resolution: for the image pixel at the top left of each 2 x 2
// block, how much of the hemisphere over its surface nearby geometry hides (screen space: the
// cloth pass's depths, and the ground found from each pixel's ray as the composite pass finds
// it). Writes x: the light left (1 = open), y: the pixel's depth along the view (0: sky).
// Taps lie on a fixed spiral turned by a quarter turn per texel of a 2 x 2 pattern; the blur
// (ao_blur.frag) averages 4 x 4 of these texels where their depths agree, which blends the four
// turns into one smooth result, the same every frame.
#include "render/frame.glsl"

#ifdef SINGLE_SAMPLE
layout(set = 0, binding = 5) uniform sampler2D scene_depth;
#else
layout(set = 0, binding = 5) uniform sampler2DMS scene_depth;
#endif

layout(location = 0) out vec2 result;

const int TAPS = 6;
// Tap k's direction before the pixel's turn: k times the golden angle (sines and cosines are
// long polynomials on a CPU device: one turn per pixel instead of one per tap).
const vec2 SPIRAL[TAPS] = vec2[](vec2(1.0000000, 0.0000000), vec2(-0.7373689, 0.6754903), vec2(0.0874257, -0.9961710),
                                 vec2(0.6084389, 0.7936008), vec2(-0.9847135, -0.1741820), vec2(0.8437553, -0.5367281));

vec3 ray(vec2 pixel)
{
    return frame.ray_base.xyz + pixel.x * frame.ray_dx.xyz + pixel.y * frame.ray_dy.xyz;
}

// Depth along the view of the ground under a pixel's centre, 0 where the ray misses it.
float ground_depth(vec2 pixel)
{
    vec3 up = frame.ground_plane.xyz;
    float toward = dot(ray(pixel), up);
    float height = dot(frame.eye.xyz, up) - frame.ground_plane.w;
    if (frame.fog.z == 0.0 || toward >= 0.0 || height <= 0.0)
        return 0.0;
    return height / -toward;
}

// Depth along the view at an image pixel: what the cloth pass drew there (reversed depth,
// cleared to 0), else the ground, else 0.
float view_depth(ivec2 p, out bool drawn)
{
    float d = texelFetch(scene_depth, p, 0).r;
    drawn = d > 0.0;
    // d = near / t · (far − near)⁻¹ · far − near / (far − near), solved for t.
    if (drawn)
        return frame.ao.x / (frame.ao.y * d + frame.ao.z);
    return ground_depth(vec2(p) + 0.5);
}

vec3 position(ivec2 p, float t)
{
    return frame.eye.xyz + t * ray(vec2(p) + 0.5);
}

void main()
{
    ivec2 size = ivec2(frame.ao_size.xy);
    ivec2 p = min(ivec2(gl_FragCoord.xy) * 2, size - 1);
    bool drawn;
    float t = view_depth(p, drawn);
    if (t == 0.0) {
        result = vec2(1.0, 0.0);
        return;
    }
    vec3 x = position(p, t);
    vec3 n = frame.ground_plane.xyz;
    if (drawn) {
        // The normal from the neighbours' positions, on each axis the side nearer in depth
        // (across an edge the other side belongs to something else).
        bool unused;
        ivec2 step_x = ivec2(p.x + 1 < size.x ? 1 : -1, 0), step_y = ivec2(0, p.y + 1 < size.y ? 1 : -1);
        float tx = view_depth(p + step_x, unused), ty = view_depth(p + step_y, unused);
        float tx2 = view_depth(p - step_x, unused), ty2 = view_depth(p - step_y, unused);
        vec3 dx = abs(tx - t) <= abs(tx2 - t) ? position(p + step_x, tx) - x : x - position(p - step_x, tx2);
        vec3 dy = abs(ty - t) <= abs(ty2 - t) ? position(p + step_y, ty) - x : x - position(p - step_y, ty2);
        if (tx == 0.0 || tx2 == 0.0)
            dx = tx == 0.0 ? x - position(p - step_x, tx2) : position(p + step_x, tx) - x;
        if (ty == 0.0 || ty2 == 0.0)
            dy = ty == 0.0 ? x - position(p - step_y, ty2) : position(p + step_y, ty) - x;
        n = normalize(cross(dx, dy));
        if (dot(n, frame.eye.xyz - x) < 0.0)
            n = -n;
    }
    float radius = frame.ao.w;
    // The radius in pixels at this depth (a pixel spans t · |ray_dx| m), at least 2, at most 64.
    float pixels = clamp(radius / (t * length(frame.ray_dx.xyz)), 2.0, 64.0);
    ivec2 cell = ivec2(gl_FragCoord.xy) & 1;
    float turn = float(cell.x + 2 * cell.y) * (1.5707963 / 4.0) + 0.3;
    mat2 rotate = mat2(cos(turn), sin(turn), -sin(turn), cos(turn));
    float bias = 0.02 * radius;
    float hidden = 0.0;
    for (int k = 0; k < TAPS; k++) {
        // Radii spread evenly out to the edge: near taps, which find contacts, as many as far.
        float r = (float(k) + 0.5) / float(TAPS) * pixels;
        ivec2 q = p + ivec2(round(r * (rotate * SPIRAL[k])));
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)))
            continue;
        bool tap_drawn;
        float tq = view_depth(q, tap_drawn);
        if (tq == 0.0)
            continue;
        vec3 v = position(q, tq) - x;
        float vv = dot(v, v);
        if (vv >= radius * radius || vv < 1e-12)
            continue;
        // How far above the surface's tangent plane the tap rises (the sine of its elevation),
        // in full out to half the radius, then fading to nothing at the radius.
        float len = sqrt(vv);
        hidden += max((dot(v, n) - bias) / len, 0.0) * min(2.0 - 2.0 * len / radius, 1.0);
    }
    result = vec2(clamp(1.0 - frame.ao_size.z * hidden / float(TAPS), 0.0, 1.0), t);
}
