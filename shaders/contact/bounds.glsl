// The displacement bounds of cloth contact (lib/contact/collide.h) as every pass that moves a
// particle reads them: where detection saw each particle and its bound, and the common shift,
// from the contact set (CONTACT_SET, default 1). Include after shared/layout.h.
#ifndef CONTACT_BOUNDS_GLSL
#define CONTACT_BOUNDS_GLSL

#ifndef CONTACT_SET
#define CONTACT_SET 1
#endif

// CONTACT_COHERENT: a shader whose invocations read what others of its workgroup wrote here in
// the same dispatch (contact_faces_fused.comp), after memoryBarrierBuffer() and barrier().
#ifdef CONTACT_COHERENT
#define CONTACT_FRAME_COHERENT coherent
#else
#define CONTACT_FRAME_COHERENT
#endif
layout(std430, set = CONTACT_SET, binding = CVK_CONTACT_BINDING_FRAME) CONTACT_FRAME_COHERENT buffer ContactFrame {
    cvk_gpu_frame frame;
    cvk_gpu_motion_bounds motion_bounds; // the decision to detect (contact_check.comp)
};
// Per particle: where detection saw it (xyz) and its bound (w; contact_bound.comp).
layout(set = CONTACT_SET, binding = CVK_CONTACT_BINDING_SEARCHED_READ, rgba32f) uniform readonly imageBuffer searched_t;

// Whether the device ended this invocation's loops early. A conformant device runs every loop
// to its end, but llvmpipe (lavapipe) ends them silently once an invocation has run 65,535
// loop iterations in all, counting every loop of every item it takes, and from then on runs
// each loop's body once: a detection so cut short misses pairs and measures bounds too large,
// and the guarantee no longer holds. A last loop of two steps whose count comes from the push
// constants (so no compiler unrolls it) runs once only when that happened; the passes that walk
// the hashes call note_loops_cut after their work with their push constants' item count, and it
// raises frame.cut (the host reports it: lib/sim/sim_watch.c). The fused sweeps ask loops_cut
// too, and raise their own flag (pd_fused.comp).
bool loops_cut(uint count)
{
    uint two = min(count, 1u) + 1u;
    uint steps = 0u;
    for (uint i = 0u; i < two; i++)
        steps++;
    return steps < two;
}

void note_loops_cut(uint count)
{
    if (loops_cut(count))
        atomicOr(frame.cut, 1u);
}

// The substep's common shift, for within_bound: read it once an invocation, before the loop
// over its particles. Read inside the loop, at every particle of a sweep, its three storage
// loads stayed there (the loop's stores might have written them), a quarter of the sweeps'
// time with self-contact (one lavapipe core: the 40 x 40 contact drape's solve 13.7 -> 9.9 ms
// a frame, the six-cloth pile's 22.5 -> 14.3). Every pass that keeps particles within their
// bounds runs in a dispatch after the decision that wrote the shift (contact_decide.comp,
// contact_faces_fused.comp), never in the one that writes it.
// motion_bounds.exceed's bits (contact_check.glsl): some particle's move would pass `redetect`
// of its bound (a detection that may wait for collision.detection_interval); the substep must
// detect (a bound centred too near a collider; where detection may wait, an attached
// particle's move or a particle already past its bound).
const uint CVK_EXCEED_MOVES = 1u, CVK_EXCEED_NOW = 2u;

vec3 bound_shift()
{
    return vec3(frame.shift_x, frame.shift_y, frame.shift_z);
}

// x kept within searched.w of where detection saw the particle plus the common shift.
vec3 within_bound(uint p, vec3 x, vec3 shift)
{
    vec4 seen = imageLoad(searched_t, int(p));
    vec3 centre = seen.xyz + shift;
    vec3 d = x - centre;
    float len2 = dot(d, d), bound = seen.w;
    return len2 > bound * bound ? centre + d * (bound / sqrt(len2)) : x;
}

#endif
