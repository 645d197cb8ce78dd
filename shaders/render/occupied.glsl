// What is drawn above the ground (occupied.comp: the cloths' vertices now and the colliders'
// box) and the rectangles of the image it can darken: the ambient occlusion pass draws only its
// own (ao.vert), the composite pass reads the occlusion and the shadow map only in its own
// (composite.vert with RECT); everywhere else nothing is near enough to anything to darken it.
// Needs render/frame.glsl.
layout(std430, set = 0, binding = 8) readonly buffer Occupied {
    uint occupied[6]; // low xyz, high xyz: floats' bits made to order (occupied.comp)
};

float from_ordered(uint u)
{
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

// The rectangle so far (clip space x, y), or the whole image once a point lies behind the eye.
struct screen_rect {
    vec2 low, high;
    bool whole;
};

void rect_add(inout screen_rect r, vec3 p)
{
    vec4 c = frame.view_proj * vec4(p, 1.0);
    if (!(c.w > 1e-6)) {
        r.whole = true;
        return;
    }
    r.low = min(r.low, c.xy / c.w);
    r.high = max(r.high, c.xy / c.w);
}

// The picture of the occupied box grown by `grow` m on every side and, with `shadows`, of
// where the box's shadow falls on the ground (its corners moved along the key light onto the
// ground plane), grown by `margin` (clip space) and held within the image; empty (a point) when
// nothing is drawn.
vec4 occupied_rect(float grow, bool shadows, vec2 margin)
{
    vec3 low = vec3(from_ordered(occupied[0]), from_ordered(occupied[1]), from_ordered(occupied[2]));
    vec3 high = vec3(from_ordered(occupied[3]), from_ordered(occupied[4]), from_ordered(occupied[5]));
    if (any(greaterThan(low, high)))
        return vec4(0.0);
    screen_rect r = screen_rect(vec2(1e30), vec2(-1e30), false);
    vec3 up = frame.ground_plane.xyz, light = frame.key_direction.xyz;
    float rise = dot(light, up);
    for (int c = 0; c < 8; c++) {
        vec3 p = mix(low - grow, high + grow, vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
        rect_add(r, p);
        if (shadows && rise > 1e-3)
            rect_add(r, p - light * (max(dot(p, up) - frame.ground_plane.w, 0.0) / rise));
    }
    if (r.whole)
        return vec4(-1.0, -1.0, 1.0, 1.0);
    return clamp(vec4(r.low - margin, r.high + margin), -1.0, 1.0);
}

// Corner `index` (0 to 3, triangle-strip order) of a rectangle.
vec4 rect_corner(vec4 rect, int index)
{
    vec2 corner = vec2(float(index & 1), float(index >> 1));
    return vec4(mix(rect.xy, rect.zw, corner), 0.0, 1.0);
}
