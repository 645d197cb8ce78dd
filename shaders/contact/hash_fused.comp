#version 450
#extension GL_GOOGLE_include_directive : require
// The whole hash build in one dispatch of ONE workgroup (lib/contact/hash.c, where the sweeps
// are fused: solver.fuse): the passes of hash_*.comp in their order, with a workgroup barrier
// between them instead of a dispatch and a pipeline barrier, and nothing at all while the
// parameters close the build (decided on the device), where the unfused build's indirect
// commands have no workgroups. The same functions in the same order, and the sort puts each
// slot's entries in index order whatever the timing, so the hash is the same bits. No
// invocation waits on another workgroup: correct on any conformant device.
#define HASH_BUILD
#define HASH_FUSED
#include "contact/hash_common.glsl"

void passed()
{
    memoryBarrierBuffer();
    barrier();
}

void main()
{
    if (hash_params.build == 0u)
        return; // the same for every invocation: read before any writes the parameters
    hash_clear_pass();
    if (pc.points == 0u)
        return;
    passed();
    hash_count_pass();
    passed();
    hash_chunk_sums_pass();
    passed();
    hash_scan_chunks_pass();
    passed();
    hash_scan_pass();
    passed();
    hash_scatter_pass();
    passed();
    hash_sort_pass();
}
