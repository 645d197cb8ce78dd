// Ambient + Lambert diffuse + Blinn-Phong specular from the key light (shadowed) and the fill
// light (seed 002 §5.4.2 used two lights and Phong; Blinn's half vector keeps the
// highlight round at grazing angles).
layout(set = 0, binding = 1) uniform sampler2DShadow shadow_map;

// Fraction of the key light that reaches `world`, by percentage-closer filtering: depth
// comparisons over a 4 x 4 texel footprint read with four gathers, each texel weighted by how
// much of a 3-texel box around the point covers it. The box slides with the point, so the
// result varies smoothly as the point moves: soft edges instead of stepped texels. The point
// first moves off the surface along its normal by about a texel (normal offset), so a lit
// face never shadows itself.
float key_visibility(vec3 world, vec3 n)
{
    float texel = frame.shadow.y;
    vec4 c = frame.light_view_proj * vec4(world + n * (1.5 * texel), 1.0);
    vec2 uv = c.xy * 0.5 + 0.5;
    // Beyond the far plane there is nothing left to cast: lit.
    float depth = min(c.z, 1.0);
    float size = frame.shadow.x;
    vec2 t = uv * size - 0.5;
    vec2 base = floor(t);
    vec2 f = t - base;
    vec2 inv = vec2(1.0 / size);
    // Per column (and row) of the footprint base - 1 .. base + 2: 1 - f, 1, 1, f.
    vec4 wx = vec4(1.0 - f.x, 1.0, 1.0, f.x);
    vec4 wy = vec4(1.0 - f.y, 1.0, 1.0, f.y);
    // Gather order: (i0, j1), (i1, j1), (i1, j0), (i0, j0).
    vec4 a = textureGather(shadow_map, base * inv, depth);
    vec4 b = textureGather(shadow_map, (base + vec2(2.0, 0.0)) * inv, depth);
    vec4 c2 = textureGather(shadow_map, (base + vec2(0.0, 2.0)) * inv, depth);
    vec4 d = textureGather(shadow_map, (base + vec2(2.0, 2.0)) * inv, depth);
    float sum = dot(vec4(a.w, a.z, a.x, a.y), vec4(wx.x * wy.x, wx.y * wy.x, wx.x * wy.y, wx.y * wy.y)) +
                dot(vec4(b.w, b.z, b.x, b.y), vec4(wx.z * wy.x, wx.w * wy.x, wx.z * wy.y, wx.w * wy.y)) +
                dot(vec4(c2.w, c2.z, c2.x, c2.y), vec4(wx.x * wy.z, wx.y * wy.z, wx.x * wy.w, wx.y * wy.w)) +
                dot(vec4(d.w, d.z, d.x, d.y), vec4(wx.z * wy.z, wx.w * wy.z, wx.z * wy.w, wx.w * wy.w));
    return sum / 9.0;
}

vec3 light(vec3 direction, vec3 color, vec3 n, vec3 v, vec3 albedo, float specular, float visible)
{
    float nl = dot(n, direction);
    if (nl <= 0.0)
        return vec3(0.0);
    vec3 h = normalize(direction + v);
    // Shininess 32 by squaring: pow() is exp(log()) on a CPU device.
    float x = max(dot(n, h), 0.0);
    x *= x;
    x *= x;
    x *= x;
    x *= x;
    float highlight = specular * x * x;
    return color * visible * nl * (albedo + highlight);
}

// n faces the viewer's side of the surface; key_visible is key_visibility() or 1.
vec3 shade(vec3 world, vec3 n, vec3 albedo, float specular, float key_visible)
{
    vec3 v = normalize(frame.eye.xyz - world);
    // A little more ambient from the sky than from the ground.
    vec3 result = frame.ambient.rgb * albedo * (0.8 + 0.2 * dot(n, frame.ground_plane.xyz));
    result += light(frame.key_direction.xyz, frame.key_color.rgb, n, v, albedo, specular, key_visible);
    result += light(frame.fill_direction.xyz, frame.fill_color.rgb, n, v, albedo, specular, 1.0);
    return result;
}
