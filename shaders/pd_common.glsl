// Particle state and projective-dynamics data shared by the solver passes.
//
// Positions are vec4 in internal order: free particles colour by colour, pinned last.
// Reads go through uniform texel buffers and writes through storage buffers: on lavapipe a
// texel fetch is a vectorised gather while a storage-buffer load is a per-lane loop (2x on a
// 100x100 sweep), and GPUs serve both well.
//
// Adjacency is slot-major and padded to MAX_DEGREE: entry s of particle p sits at
// s * pc.stride + p, so neighbouring invocations read neighbouring texels; padding entries
// point at p itself with zero stiffness and cost nothing but their fetch.

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint MAX_DEGREE = 4;

layout(set = 0, binding = 0) uniform samplerBuffer src;          // iterate read (xyz)
layout(set = 0, binding = 1) uniform samplerBuffer dst_read;     // iterate being written, read
layout(std430, set = 0, binding = 2) writeonly buffer Dst { vec4 dst[]; };
layout(set = 0, binding = 3) uniform samplerBuffer y_read;       // xyz: prediction, w: m/h^2
layout(std430, set = 0, binding = 4) writeonly buffer Inertial { vec4 y[]; };
layout(set = 0, binding = 5) uniform samplerBuffer prev_read;    // xyz: x at last substep, w: m/h^2
layout(std430, set = 0, binding = 6) writeonly buffer Previous { vec4 prev[]; };
layout(set = 0, binding = 7) uniform samplerBuffer rhs_read;     // xyz: b, w: 1/diag
layout(std430, set = 0, binding = 8) writeonly buffer Rhs { vec4 rhs[]; };
layout(set = 0, binding = 9) uniform usamplerBuffer adjacency;   // x: neighbour, y: bits of k
layout(set = 0, binding = 10) uniform samplerBuffer adjacency_kl; // k * rest length

layout(push_constant) uniform Push {
    uint first;       // first particle of this dispatch
    uint count;       // particles in this dispatch
    uint stride;      // free particle count: adjacency slot stride
    uint pad0;
    float inv_h2;     // 1 / h^2
    float omega;      // SOR factor (Gauss-Seidel) or relaxation (Jacobi)
    float cheb;       // Chebyshev weight of this sweep; 1 = plain sweep
    float keep;       // 1 - damping (0 when integration is off)
    vec4 gravity_h2;  // h^2 g (0 when integration is off)
} pc;

// Invocations stride over the dispatch, so a few workgroups can cover many particles.
uint invocation_stride()
{
    return gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

vec3 fetch_position(samplerBuffer positions, uint index)
{
    return texelFetch(positions, int(index)).xyz;
}

// One spring's part of the local step, folded into the right-hand side:
// k L (t_p - t_c) / |t_p - t_c| from the positions t at the start of the outer iteration.
// Coincident particles give no direction and contribute nothing.
vec3 projected(vec3 tp, vec3 tn, float kl)
{
    vec3 d = tp - tn;
    float len = length(d);
    return len > 0.0 ? (kl / len) * d : vec3(0.0);
}
