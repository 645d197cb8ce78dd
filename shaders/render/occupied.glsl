// What is drawn above the ground (occupied.comp: the cloths' vertices now and the colliders'
// box) and the parts of the image it can darken: the ambient occlusion pass draws only its own
// rectangle (ao.vert), the composite pass reads the shadow map only over the box's shadow on the
// ground (composite.vert with FOOTPRINT) and the cloth pass and the occlusion only in their
// rectangle (with RECT); everywhere else nothing is near enough to anything to darken it.
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

// The box, grown by how far the drawn surfaces reach beyond the vertices (a thick cloth's faces)
// and by `grow` m; false when nothing is drawn.
bool occupied_box(float grow, out vec3 low, out vec3 high)
{
    grow += frame.post.y;
    low = vec3(from_ordered(occupied[0]), from_ordered(occupied[1]), from_ordered(occupied[2])) - grow;
    high = vec3(from_ordered(occupied[3]), from_ordered(occupied[4]), from_ordered(occupied[5])) + grow;
    return all(lessThanEqual(low, high));
}

// The picture of the occupied box grown by `grow` m on every side, grown by `margin` (clip
// space) and held within the image; empty (a point) when nothing is drawn.
vec4 occupied_rect(float grow, vec2 margin)
{
    vec3 low, high;
    if (!occupied_box(grow, low, high))
        return vec4(0.0);
    screen_rect r = screen_rect(vec2(1e30), vec2(-1e30), false);
    for (int c = 0; c < 8; c++)
        rect_add(r, mix(low, high, vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1)));
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

// The corners of each face of a box (corner c: x low or high by bit 0, y by bit 1, z by bit 2),
// two triangles a face.
const int BOX_TRIANGLES[36] = int[](0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                                    2, 3, 7, 2, 7, 6, 0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6);

// Vertex `index` (0 to 35) of the occupied box grown by `grow` m with each corner moved along the
// key light onto the ground plane: the 12 triangles cover the box's shadow on the ground (the
// shadow of a convex solid is the hull of its corners' shadows, and each point of the hull lies
// under some face). The depth is set so that only the near plane clips (no far plane: a long
// shadow reaches past the cloth's depth range); all at one point when nothing casts a shadow.
vec4 footprint_corner(float grow, int index)
{
    vec3 low, high;
    vec3 up = frame.ground_plane.xyz, light = frame.key_direction.xyz;
    float rise = dot(light, up);
    if (!occupied_box(grow, low, high) || rise <= 1e-3)
        return vec4(0.0, 0.0, 0.5, 1.0);
    int c = BOX_TRIANGLES[index];
    vec3 p = mix(low, high, vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1));
    p -= light * ((dot(p, up) - frame.ground_plane.w) / rise);
    vec4 clip = frame.view_proj * vec4(p, 1.0);
    clip.z = clip.w - frame.ao.z;
    return clip;
}
