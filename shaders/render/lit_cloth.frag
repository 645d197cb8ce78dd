#version 450
#extension GL_GOOGLE_include_directive : require
// Cloth pass: lit and shadowed cloth over a transparent background, multisampled; the
// composite pass puts it over the ground and sky. The colliders (collider.vert) are shaded
// here too, with their own colour and a Blinn-Phong highlight (its strength and exponent from
// their material's roughness); a cloth gets diffuse light, a
// sheen lobe and the light that comes through it from its other face. Both faces are drawn; a
// back face is lit with the flipped normal (and, with material.back_color, its own colour), so
// the side away from the light is darker and the side towards it lit, whichever way the cloth
// turns (seed 002 lit both faces alike, its §9). Built with COLLIDER for the colliders, whose
// texture is projected from their texture frame (collider.vert) rather than read at uv.
#include "render/frame.glsl"
#include "render/lighting.glsl"

// The ground hides what is below it (a cloth without a collider falls through).
layout(constant_id = 0) const bool CLIP_BELOW_GROUND = true;
// Some cloth has a texture or a normal map: read them where the material says so.
layout(constant_id = 1) const bool TEXTURED = false;
// The cloths' pipeline (fabric shading); false: the colliders' (Blinn-Phong). A constant, not
// the material's flag: a CPU device would run both shadings for every pixel.
layout(constant_id = 2) const bool FABRIC = true;

layout(push_constant) uniform Material {
    vec4 albedo; // rgb: linear colour of this cloth; w: 1 where its texture replaces it
    vec4 back;   // rgb: the back face's colour; w: 1 to use it, 0 for the front's. Colliders:
                 // x: the texture's repeats per metre
    vec4 fabric; // cloths: x: sheen; y: its roughness. Colliders: the highlight's strength, exponent
    vec4 slab;   // a thick cloth's face: x: its offset (lit_cloth.vert); y: the thickness; z: the
                 // normal map's strength, 0 for none
} material;

// The draw's texture (sRGB, decoded to linear by the sampler; mipmapped, trilinear).
layout(set = 0, binding = 3) uniform sampler2D albedo_map;
// The draw's normal map (tangent space, unorm; a flat stand-in without one).
layout(set = 0, binding = 7) uniform sampler2D normal_map;

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 world_normal;
// Centroid: with multisampling a pixel's centre may lie outside a triangle that covers some of
// its samples, and a coordinate extrapolated there could read beyond the cloth's part of the
// texture.
layout(location = 2) centroid in vec2 uv;
#ifdef COLLIDER
layout(location = 3) in vec3 texture_point;  // m, in the collider's texture frame
layout(location = 4) in vec3 texture_normal; // the normal in that frame
#endif
#ifndef COLLIDER
// Where the key light's shadow is looked up: under a curved triangle (render.smooth, pn.tese)
// the flat one's point, which is what the shadow pass drew; the curved surface bulges out of the
// flat triangles and would fall into their shadow on the lit side (dark blotches on crumples).
layout(location = 3) in vec3 shadow_world;
#endif
#ifdef VERTEX_LIGHT
// The light found at the vertices (lit_cloth.vert), per face: albedo · d + sheen · s.
layout(location = 4) in vec3 front_d;
layout(location = 5) in vec3 front_s;
layout(location = 6) in vec3 back_d;
layout(location = 7) in vec3 back_s;
#endif
layout(location = 0) out vec4 color;

// The normal tilted by the normal map: its tangent along u and bitangent along v found from how
// the position and the texture coordinates change across the pixel (a cotangent frame, Schüler
// 2006: no tangents stored, and it follows the cloth as it deforms); the map's x and y scaled
// by `strength`.
vec3 mapped_normal(vec3 n, float strength)
{
    vec3 dp1 = dFdx(world), dp2 = dFdy(world);
    vec2 duv1 = dFdx(uv), duv2 = dFdy(uv);
    vec3 dp2perp = cross(dp2, n), dp1perp = cross(n, dp1);
    vec3 t = dp2perp * duv1.x + dp1perp * duv2.x;
    vec3 b = dp2perp * duv1.y + dp1perp * duv2.y;
    float size = max(dot(t, t), dot(b, b));
    vec3 m = texture(normal_map, uv).xyz * 2.0 - 1.0;
    m.xy *= strength;
    vec3 tilted = size > 0.0 ? (t * m.x + b * m.y) * inversesqrt(size) + n * m.z : n;
    float len = length(tilted);
    return len > 0.0 ? tilted / len : n;
}

#ifdef COLLIDER
// The collider's texture seen along each axis of its frame (a box's face and a plane: one of
// them), weighted by the fourth power of the normal's part along it; weights under 2% of the
// whole are dropped, so most pixels read one projection. The derivatives come from the point,
// outside the branches, for the mip level.
vec3 projected_albedo()
{
    vec3 p = texture_point * material.back.x;
    vec3 dx = dFdx(p), dy = dFdy(p);
    vec3 w = abs(texture_normal);
    w *= w;
    w *= w;
    w /= max(w.x + w.y + w.z, 1e-20);
    w = max(w - 0.02, 0.0);
    w /= max(w.x + w.y + w.z, 1e-20);
    vec3 sum = vec3(0.0);
    if (w.x > 0.0)
        sum += w.x * textureGrad(albedo_map, vec2(p.z, -p.y), vec2(dx.z, -dx.y), vec2(dy.z, -dy.y)).rgb;
    if (w.y > 0.0)
        sum += w.y * textureGrad(albedo_map, p.xz, dx.xz, dy.xz).rgb;
    if (w.z > 0.0)
        sum += w.z * textureGrad(albedo_map, vec2(p.x, -p.y), vec2(dx.x, -dx.y), vec2(dy.x, -dy.y)).rgb;
    return sum;
}
#endif

#ifdef VERTEX_LIGHT
// A cloth lit at its vertices: the albedo (the texture's, or the back face's own colour) times
// the light of the face seen.
vec3 vertex_lit()
{
    vec3 albedo = TEXTURED && material.albedo.w > 0.5 ? texture(albedo_map, uv).rgb : material.albedo.rgb;
    if (!gl_FrontFacing && material.back.w > 0.5)
        albedo = material.back.rgb;
    vec3 sheen = material.fabric.x * sqrt(albedo);
    return gl_FrontFacing ? albedo * front_d + sheen * front_s : albedo * back_d + sheen * back_s;
}
#endif

void main()
{
    if (CLIP_BELOW_GROUND && dot(world, frame.ground_plane.xyz) < frame.ground_plane.w)
        discard;
#ifdef VERTEX_LIGHT
    color = vec4(sqrt(clamp(0.5 * vertex_lit(), 0.0, 1.0)), 1.0);
#else
    float len = length(world_normal);
    vec3 n = len > 0.0 ? world_normal / len : normalize(frame.eye.xyz - world);
    if (TEXTURED && material.slab.z > 0.0)
        n = mapped_normal(n, material.slab.z);
    if (!gl_FrontFacing)
        n = -n;
    // The key light's shadow on whichever face it falls on: lighting that face, or, on a cloth,
    // coming through to the other. Through a thick cloth's face the shadow is looked up on the
    // slab's other face, so the slab does not shadow the light that crosses it.
    bool towards = dot(n, frame.key_direction.xyz) > 0.0;
#ifdef COLLIDER
    vec3 lookup = world;
#else
    vec3 lookup = shadow_world;
#endif
    float visible = key_visibility(towards ? lookup : lookup - n * material.slab.y, towards ? n : -n);
#ifdef COLLIDER
    vec3 albedo = TEXTURED && material.albedo.w > 0.5 ? projected_albedo() : material.albedo.rgb;
#else
    vec3 albedo = TEXTURED && material.albedo.w > 0.5 ? texture(albedo_map, uv).rgb : material.albedo.rgb;
#endif
    if (!gl_FrontFacing && material.back.w > 0.5)
        albedo = material.back.rgb;
    vec3 shaded;
    if (FABRIC)
        shaded = shade_fabric(world, n, albedo, material.fabric.x * sqrt(albedo), material.fabric.y, visible);
    else
        shaded = shade(world, n, albedo, material.fabric.x, material.fabric.y, towards ? visible : 0.0);
    // Stored as the square root of half the linear light: the composite pass squares it back
    // (and doubles it) before averaging the samples, 8 bits of it are about as fine in the dark
    // as sRGB, and light up to twice white reaches the highlights' roll-off.
    color = vec4(sqrt(clamp(0.5 * shaded, 0.0, 1.0)), 1.0);
#endif
}
