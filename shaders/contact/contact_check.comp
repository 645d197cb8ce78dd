#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive candidate search, first half (lib/contact/collide.h), one pass over the particles: the
// bounds of every displacement since the last search (d = x - where the search saw the
// particle), per axis. No d is farther from the bounds' centre than half their diagonal, and
// two particles' displacements differ by at most twice that (contact_decide.comp): a cloth
// that moves as one needs no search. Atomic min and max on order-preserving bits of the
// floats, so the result does not depend on thread timing.
layout(local_size_x_id = 0) in;
#include "shared/layout.h"
#define CONTACT_SET 0
#include "contact/collide.glsl"
CVK_DECLARE_PUSH(CVK_CONTACT_PUSH_FIELDS)

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    vec3 low = vec3(3.0e38), high = vec3(-3.0e38);
    bool finite = true;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += stride) {
        uint p = pc.first + i;
        vec3 d = contact_x(p) - texelFetch(searched_t, int(p)).xyz;
        finite = finite && all(lessThanEqual(abs(d), vec3(3.0e38)));
        low = min(low, d);
        high = max(high, d);
    }
    if (!finite) { // a cloth that blew up: bounds no search can be skipped for
        low = vec3(-3.0e38);
        high = vec3(3.0e38);
    }
    if (low.x <= high.x) {
        atomicMin(motion_bounds.low_x, ordered(low.x));
        atomicMin(motion_bounds.low_y, ordered(low.y));
        atomicMin(motion_bounds.low_z, ordered(low.z));
        atomicMax(motion_bounds.high_x, ordered(high.x));
        atomicMax(motion_bounds.high_y, ordered(high.y));
        atomicMax(motion_bounds.high_z, ordered(high.z));
    }
}
