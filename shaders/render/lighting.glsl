// Sky and ground light (a hemisphere) + Lambert diffuse + Blinn-Phong specular from the key
// light (shadowed) and the fill light (seed 002 §5.4.2 used two lights and Phong; Blinn's half
// vector keeps the highlight round at grazing angles).
// render.soft_shadows (and a key light wider than 0) and render.sky_light, as specialization
// constants: a CPU device runs both sides of a branch, so an effect switched off must be
// compiled out, not skipped.
layout(constant_id = 4) const bool SOFT_SHADOWS = true;
layout(constant_id = 5) const bool SKY_LIGHT = true;

layout(set = 0, binding = 1) uniform sampler2DShadow shadow_map;
// The same map's depths, for the blocker search of the soft shadows.
layout(set = 0, binding = 4) uniform sampler2D shadow_depth;

// Depth comparisons over a 4 x 4 texel footprint read with four gathers, each texel weighted by
// how much of a 3-texel box around the point covers it. The box slides with the point, so the
// result varies smoothly as the point moves: soft edges instead of stepped texels.
float pcf_box(vec2 uv, float depth)
{
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

// Sum of the depths in `g` nearer the light than `depth`, and their count.
vec2 blockers(vec4 g, float depth)
{
    vec4 in_front = step(g, vec4(depth));
    return vec2(dot(g, in_front), dot(in_front, vec4(1.0)));
}

// Vogel's spiral: tap k at radius sqrt((k + 0.5) / 8), turned by k golden angles (constants:
// sines and cosines are long polynomials on a CPU device).
const vec2 VOGEL[8] = vec2[](vec2(0.2500000, 0.0000000), vec2(-0.3192901, 0.2924959), vec2(0.0488725, -0.5568765),
                             vec2(0.4024445, 0.5249176), vec2(-0.7385351, -0.1306365), vec2(0.6996049, -0.4450314),
                             vec2(-0.2340042, 0.8704838), vec2(-0.4462713, -0.8592682));

// Fraction of the key light that reaches `world`. The point first moves off the surface along
// its normal by about a texel (normal offset), so a lit face never shadows itself. With soft
// shadows (percentage-closer soft shadows): the mean depth of what lies between the point and
// the light over a search square, from four gathers of the raw depths, gives the penumbra, as
// wide as the key light's angular size times the distance from that blocker to the point; the
// comparisons are then averaged over a disc that wide (8 bilinear comparisons on a fixed
// spiral, so the same pixel gets the same value every frame). A CPU device runs every
// instruction for every pixel whatever the branches, so the cost is fixed: 12 reads of the map
// against the box filter's 4.
float key_visibility(vec3 world, vec3 n)
{
    float texel = frame.shadow.y;
    vec4 c = frame.light_view_proj * vec4(world + n * (1.5 * texel), 1.0);
    vec2 uv = c.xy * 0.5 + 0.5;
    // Beyond the far plane there is nothing left to cast: lit.
    float depth = min(c.z, 1.0);
    if (!SOFT_SHADOWS)
        return pcf_box(uv, depth);
    vec2 inv = vec2(1.0 / frame.shadow.x);
    float search = frame.soft.y;
    // Blockers: at least two texels' depth nearer (the bias of the shadow pass is smaller).
    float test = depth - 2.0 * texel / frame.soft.z;
    vec2 found = blockers(textureGather(shadow_depth, uv + vec2(-0.5, -0.5) * search * inv), test);
    found += blockers(textureGather(shadow_depth, uv + vec2(0.5, -0.5) * search * inv), test);
    found += blockers(textureGather(shadow_depth, uv + vec2(-0.5, 0.5) * search * inv), test);
    found += blockers(textureGather(shadow_depth, uv + vec2(0.5, 0.5) * search * inv), test);
    // Penumbra radius in texels: light-depth distance (m) times the light's spread per metre; at
    // least the box filter's 1.5 texels (also where no blocker was found: the taps then agree).
    float blocker = found.y > 0.0 ? found.x / found.y : depth;
    float radius = clamp((depth - blocker) * frame.soft.z * frame.soft.x, 1.5, search);
    float sum = 0.0;
    for (int k = 0; k < 8; k++)
        sum += texture(shadow_map, vec3(uv + radius * VOGEL[k] * inv, depth));
    return sum / 8.0;
}

vec3 light(vec3 direction, vec3 color, vec3 n, vec3 v, vec3 albedo, float specular, float shininess,
           float visible)
{
    float nl = dot(n, direction);
    if (nl <= 0.0)
        return vec3(0.0);
    vec3 h = normalize(direction + v);
    float x = max(dot(n, h), 0.0);
    float highlight;
    if (shininess == 32.0) {
        // The default by squaring: pow() is exp(log()) on a CPU device.
        x *= x;
        x *= x;
        x *= x;
        x *= x;
        highlight = specular * x * x;
    } else {
        highlight = specular * pow(x, shininess);
    }
    return color * visible * nl * (albedo + highlight);
}

// Light from everywhere: with render.sky, the sky's light from above and the ground's bounce
// from below, blended by the normal's tilt; without, the flat ambient.
vec3 surroundings(vec3 n)
{
    float up = dot(n, frame.ground_plane.xyz);
    if (!SKY_LIGHT)
        return frame.ambient.rgb * (0.8 + 0.2 * up);
    return mix(frame.bounce.rgb, frame.sky.rgb, 0.5 + 0.5 * up);
}

// The "Charlie" sheen lobe (Estevez and Kulla 2017: a sine-power distribution of the fibres'
// half vectors, brightest where the light grazes) with Neubelt and Pettineo's visibility term,
// times pi (the diffuse term here is albedo · n·l, with no 1 / pi).
float sheen_lobe(float nh, float nl, float nv, float roughness)
{
    float inv = 1.0 / roughness;
    float sin2 = max(1.0 - nh * nh, 0.0078125);
    float d = (2.0 + inv) * pow(sin2, 0.5 * inv) / 6.2831853;
    return 3.14159265 * d / (4.0 * (nl + nv - nl * nv));
}

// Share of the light on one face of a cloth that the other face gives off (thin fabric lets
// light through: a back-lit cloth glows in its colour instead of going black).
const float TRANSMITTED = 0.25;

// One light on a fabric, added to what multiplies the albedo (d: diffuse on the lit face, the
// transmitted share on the other) and to what multiplies the sheen colour (s).
void fabric_light(vec3 direction, vec3 color, vec3 n, vec3 v, float roughness, float visible, inout vec3 d,
                  inout vec3 s)
{
    float nl = dot(n, direction);
    if (nl <= 0.0) {
        d += color * visible * (-nl) * TRANSMITTED;
        return;
    }
    float nv = max(dot(n, v), 1e-3);
    float nh = dot(n, normalize(direction + v));
    vec3 lit = color * visible * nl;
    d += lit;
    s += lit * sheen_lobe(nh, nl, nv, roughness);
}

// A cloth's light at `world` as two factors, so that its colour is albedo · d + sheen · s (the
// albedo may come later, from a texture): n faces the viewer's side; key_visible is
// key_visibility() on the side the key light falls on.
void fabric_terms(vec3 world, vec3 n, float roughness, float key_visible, out vec3 d, out vec3 s)
{
    vec3 v = normalize(frame.eye.xyz - world);
    d = surroundings(n);
    s = vec3(0.0);
    fabric_light(frame.key_direction.xyz, frame.key_color.rgb, n, v, roughness, key_visible, d, s);
    fabric_light(frame.fill_direction.xyz, frame.fill_color.rgb, n, v, roughness, 1.0, d, s);
}

// A cloth's colour; sheen: the sheen lobe's colour.
vec3 shade_fabric(vec3 world, vec3 n, vec3 albedo, vec3 sheen, float roughness, float key_visible)
{
    vec3 d, s;
    fabric_terms(world, n, roughness, key_visible, d, s);
    return albedo * d + sheen * s;
}

// n faces the viewer's side of the surface; key_visible is key_visibility() or 1.
vec3 shade(vec3 world, vec3 n, vec3 albedo, float specular, float shininess, float key_visible)
{
    vec3 v = normalize(frame.eye.xyz - world);
    vec3 result = surroundings(n) * albedo;
    result += light(frame.key_direction.xyz, frame.key_color.rgb, n, v, albedo, specular, shininess, key_visible);
    result += light(frame.fill_direction.xyz, frame.fill_color.rgb, n, v, albedo, specular, shininess, 1.0);
    return result;
}
