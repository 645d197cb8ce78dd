#version 450
#extension GL_GOOGLE_include_directive : require
// The indirect commands of a hash build decided on the device (lib/contact/hash.h): each pass's
// workgroups (the push data, as the plan would dispatch them directly) while the parameters
// open the build, none while they close it, so a skipped build costs its six dispatches no
// workgroups. This is the only reader of `build`: a build dispatched directly always runs.
layout(local_size_x = 1) in;
#include "contact/hash_common.glsl"
CVK_DECLARE_PUSH(CVK_HASH_COMMANDS_PUSH_FIELDS)

void main()
{
    uint open = hash_params.build != 0u ? 1u : 0u;
    uint groups[CVK_HASH_BUILD_PASSES] = uint[](pc.clear, pc.count, pc.chunk_sums, pc.scan_chunks,
                                                pc.scan, pc.scatter);
    for (uint i = 0u; i < uint(CVK_HASH_BUILD_PASSES); i++) {
        hash_commands[3u * i] = groups[i] * open;
        hash_commands[3u * i + 1u] = 1u;
        hash_commands[3u * i + 2u] = 1u;
    }
}
