// The decision's check over the particles (lib/contact/collide.h), its two phases as
// functions over items index, index + stride, ... of [pc.first, pc.first + pc.count), for
// contact_check.comp (a dispatch a phase) and contact_faces_fused.comp (the whole decision in one
// workgroup): include after contact/collide.glsl.
const float BIG = 3.0e38;

void bound_axes(vec3 low, vec3 high, vec3 vlow, vec3 vhigh)
{
    if (low.x > high.x)
        return;
    atomicMin(motion_bounds.e_low_x, ordered(low.x));
    atomicMin(motion_bounds.e_low_y, ordered(low.y));
    atomicMin(motion_bounds.e_low_z, ordered(low.z));
    atomicMax(motion_bounds.e_high_x, ordered(high.x));
    atomicMax(motion_bounds.e_high_y, ordered(high.y));
    atomicMax(motion_bounds.e_high_z, ordered(high.z));
    atomicMin(motion_bounds.v_low_x, ordered(vlow.x));
    atomicMin(motion_bounds.v_low_y, ordered(vlow.y));
    atomicMin(motion_bounds.v_low_z, ordered(vlow.z));
    atomicMax(motion_bounds.v_high_x, ordered(vhigh.x));
    atomicMax(motion_bounds.v_high_y, ordered(vhigh.y));
    atomicMax(motion_bounds.v_high_z, ordered(vhigh.z));
}

// Phase 1: whether some particle would leave its bound (motion_bounds.exceed); x_n kept as
// the next substep's x_before.
void check_exceed(uint index, uint stride)
{
    vec3 next = vec3(motion_bounds.next_x, motion_bounds.next_y, motion_bounds.next_z);
    // The bounds the last substep kept to (the decision sets the next shift after this).
    vec3 shift = vec3(frame.shift_x, frame.shift_y, frame.shift_z);
    bool holding = contact_u.detection_interval > 1u;
    bool moves = false, now = false;
    for (uint i = index; i < pc.count; i += stride) {
        uint p = pc.first + i;
        vec4 seen = imageLoad(searched_t, int(p));
        vec3 x = contact_x(p);
        vec3 e = 2.0 * x - previous[p].xyz - seen.xyz - next;
        previous[p] = vec4(x, 0.0); // the next substep's x_before
        bool over = !(length(e) <= contact_u.redetect * seen.w);
        moves = moves || over;
        // Nor may the shift centre the bound nearer a collider than the thickness less
        // the bound: the collider's push could then take the particle past its bound
        // (pd_contact.glsl). Where detection may wait, neither does it for an attached
        // particle's move (held at its bound, it would not follow its attachment: the twist,
        // contact-twist.json, ended 1,066 % stretched at interval 4), nor for a particle
        // already past its bound — a collider's push that won over it: the bounds hold the
        // others only while it keeps to its own (1 % over it: the rounding of a place on it).
        vec3 from_centre = x - seen.xyz - shift;
        now = now || nearest_solid(p, seen.xyz + next, true) < contact_u.thickness - seen.w ||
              (holding && ((over && p >= contact_u.free_count) ||
                           dot(from_centre, from_centre) > 1.0201 * seen.w * seen.w));
    }
    uint exceed = (moves ? CVK_EXCEED_MOVES : 0u) | (now ? CVK_EXCEED_NOW : 0u);
    if (exceed != 0u)
        atomicOr(motion_bounds.exceed, exceed);
}

// Phase 0: the bounds of the extrapolated displacements and of the last substep's, whether a
// particle is near a collider, and the particles held at their bounds counted.
void check_moves(uint index, uint stride)
{
    vec3 low = vec3(BIG), high = vec3(-BIG), vlow = vec3(BIG), vhigh = vec3(-BIG);
    bool near = false;
    // The bounds the last substep kept to: its shift (the decision sets the next after this),
    // none after the state was written (frame.force: no substep ran under them).
    vec3 shift = vec3(frame.shift_x, frame.shift_y, frame.shift_z);
    bool counting = frame.force == 0u;
    uint held = 0u;
    for (uint i = index; i < pc.count; i += stride) {
        uint p = pc.first + i;
        vec3 x = contact_x(p);
        vec4 seen = imageLoad(searched_t, int(p));
        vec3 from_centre = x - seen.xyz - shift;
        float near_bound = contact_u.redetect * seen.w;
        held += counting && p < contact_u.free_count &&
                        dot(from_centre, from_centre) >= near_bound * near_bound
                    ? 1u
                    : 0u;
        vec3 v = x - imageLoad(previous_t, int(p)).xyz;
        // Within the thickness, the radius and twice its last move of a collider: one may
        // stop it while the others move on, so a detection takes no shift
        // (contact_decide.comp).
        float reach = contact_u.thickness + contact_u.radius + 2.0 * length(v);
        near = near || !(nearest_solid(p, x, true) >= reach);
        vec3 e = x - seen.xyz + v;
        bool finite = all(lessThanEqual(abs(e), vec3(BIG))) && all(lessThanEqual(abs(v), vec3(BIG)));
        low = min(low, finite ? e : vec3(-BIG));
        high = max(high, finite ? e : vec3(BIG));
        vlow = min(vlow, finite ? v : vec3(-BIG));
        vhigh = max(vhigh, finite ? v : vec3(BIG));
    }
    bound_axes(low, high, vlow, vhigh);
    if (near)
        atomicOr(motion_bounds.near, 1u);
    if (held > 0u)
        atomicAdd(motion_bounds.held, held);
}
