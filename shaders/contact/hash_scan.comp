#version 450
#extension GL_GOOGLE_include_directive : require
// One pass of the hash build, a dispatch of its own: hash_scan_pass (contact/hash_common.glsl).
#define HASH_BUILD
#include "contact/hash_common.glsl"

void main()
{
    hash_scan_pass();
}
