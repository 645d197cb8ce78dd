// Contact between the projective-dynamics iterations: a particle's displacement is kept off
// the other cloths' triangles found for it this substep and out of every collider
// (collide.glsl). Triangle corners are read from src (the iterate before), never from the
// buffer being written, so the result does not depend on the order of invocations.
// Specialised: collider types the scene lacks (COLLIDER_TYPES, id 3) and self-contact
// (SELF, id 4) compile to nothing — on lavapipe both sides of a branch run.
#define CONTACT_TYPES_ID 3
#include "collide.glsl"

layout(constant_id = 4) const bool SELF = false;
const bool COLLIDERS = COLLIDER_TYPES != 0u;
// Self-contact alone: the pass visits only the particles the last search listed with
// candidates (lib/collide.h, "Patches"); with colliders it visits every particle.
const bool LISTED = SELF && !COLLIDERS;

vec3 pd_contact(uint p, vec3 u)
{
    vec3 x0 = fetch(x_read, p);
    if (SELF) {
        vec3 xp = x0 + u;
        for (uint k = 0u; k < uint(CVK_CONTACTS_PER_PARTICLE); k++) {
            uint e = contact_entry(p * uint(CVK_CONTACTS_PER_PARTICLE) + k);
            if (e == CVK_NO_CONTACT)
                break;
            uvec4 t = contact_triangle(e >> 1u);
            vec3 a0 = fetch(x_read, t.x), b0 = fetch(x_read, t.y), c0 = fetch(x_read, t.z);
            xp = collide_triangle(x0, xp, a0, b0, c0, a0 + fetch(src, t.x), b0 + fetch(src, t.y),
                                  c0 + fetch(src, t.z));
        }
        // At most half a thickness of push in one pass, however many triangles push: a
        // particle crowded by several layers was otherwise thrown by their summed corrections.
        vec3 push = xp - (x0 + u);
        float length_push = length(push);
        float most = 0.5 * contact_u.thickness;
        u += length_push > most ? push * (most / length_push) : push;
    }
    if (COLLIDERS)
        u = collide_colliders(x0, u);
    return u;
}
