#version 450
#extension GL_GOOGLE_include_directive : require
// Verlet prediction in displacement form: the last substep's displacement u (in src) carries
// the velocity, so the predicted displacement is y = u (1 - damping) + h^2 g; it is also the
// first iterate. Pinned particles are never dispatched.
//
// For the divergence watch, one invocation counts the substep (finalize reads the count after
// the barriers between them), and every particle's first four springs (its first quad of slots)
// are measured in the positions the substep starts from, which no pass writes while this one
// runs: one past RUNAWAY_STRETCH times its rest length raises the flag finalize acts on. Four
// springs are enough: a solve that blows up stretches every spring around where it starts.
#include "pd_common.glsl"

const float RUNAWAY_STRETCH = 10.0; // lib/sim.h, CVK_DIVERGED_STRETCH

bool overstretched(uint p)
{
    uvec4 c = quad_neighbours(0u, p);
    vec4 k = quad_k(0u, p);
    vec4 kl = texelFetch(adjacency_kl, int(p));
    vec3 xp = fetch(x_read, p);
    bool over = false;
    for (uint j = 0u; j < 4u; j++) {
        vec3 d = fetch(x_read, c[j]) - xp;
        float limit = RUNAWAY_STRETCH * kl[j] / max(k[j], 1e-30);
        over = over || (k[j] > 0.0 && dot(d, d) > limit * limit);
    }
    return over;
}

void main()
{
    if (gl_GlobalInvocationID.x == 0u && pc.count > 0u)
        watch.substep += 1u;
    for (uint i = gl_GlobalInvocationID.x; i < pc.count; i += invocation_stride()) {
        uint p = pc.first + i;
        vec3 yp = fetch(src, p) * pc.keep + pc.gravity_h2.xyz;
        y[p] = vec4(yp, texelFetch(x_read, int(p)).w);
        dst[p] = vec4(yp, 0.0);
        if (pc.max_u2 > 0.0 && overstretched(p)) {
            watch.stretched = 1u;
            atomicMin(watch.particle, p);
        }
    }
}
