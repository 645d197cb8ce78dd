#version 450
#extension GL_GOOGLE_include_directive : require
// Each free particle's share of the air's force, summed over its triangles in a fixed order
// (the same bits for any dispatch shape), as the displacement h^2 F / m the prediction adds.
// Invocation 0 counts the substep in the frame state when no pass before did.
layout(local_size_x_id = 0) in;

#include "features/aero.glsl"

void main()
{
    if (pc.count == 0u)
        return;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint p = gl_GlobalInvocationID.x; p < pc.count; p += stride) {
        vec3 sum = vec3(0.0);
        uint first = texelFetch(incidence_t, int(p)).x, end = texelFetch(incidence_t, int(p + 1u)).x;
        for (uint k = first; k < end; k++)
            sum += texelFetch(forces_t, int(texelFetch(incidence_t, int(pc.count + 1u + k)).x)).xyz;
        air[p] = vec4(sum / texelFetch(x_t, int(p)).w, 0.0);
    }
    if (gl_GlobalInvocationID.x == 0u && pc.counted == 0u)
        frame.step += 1u;
}
