#version 450
// The box the cloths occupy now (lib/render/render_occupied.c): the least and greatest of the
// drawn vertices' coordinates, as atomic minima and maxima on the floats' bits made to order as
// the floats do (a non-negative float's bits with the sign bit set, a negative one's inverted),
// so the result does not depend on thread timing. The buffer starts as the colliders' box (the
// host writes it before the dispatch); non-finite vertices are passed over.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly buffer Vertices { vec4 vertices[]; }; // position, normal
layout(std430, set = 0, binding = 1) buffer Occupied { uint box[6]; };             // low xyz, high xyz

layout(push_constant) uniform Push {
    uint vertex_count;
} pc;

uvec3 ordered(vec3 f)
{
    uvec3 b = floatBitsToUint(f);
    return mix(b | 0x80000000u, ~b, greaterThanEqual(b, uvec3(0x80000000u)));
}

void main()
{
    uvec3 low = uvec3(0xffffffffu), high = uvec3(0u);
    for (uint v = gl_GlobalInvocationID.x; v < pc.vertex_count; v += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        vec3 p = vertices[2u * v].xyz;
        if (!all(lessThanEqual(abs(p), vec3(1e30))))
            continue;
        uvec3 o = ordered(p);
        low = min(low, o);
        high = max(high, o);
    }
    if (low.x > high.x)
        return; // no vertex here
    atomicMin(box[0], low.x);
    atomicMin(box[1], low.y);
    atomicMin(box[2], low.z);
    atomicMax(box[3], high.x);
    atomicMax(box[4], high.y);
    atomicMax(box[5], high.z);
}
