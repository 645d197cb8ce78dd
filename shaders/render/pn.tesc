#version 450
#extension GL_GOOGLE_include_directive : require
// Curved triangles (render.smooth), control stage: each cloth triangle is one patch of its
// three vertices, passed on unchanged; every edge and the inside are cut into SEGMENTS. Edges
// shared by two triangles get the same level on both sides, so the surface has no cracks.
layout(vertices = 3) out;

layout(constant_id = 7) const int SEGMENTS = 3;

layout(location = 0) in vec3 world[];
layout(location = 1) in vec3 world_normal[];
layout(location = 2) in vec2 uv[];
layout(location = 3) in vec3 shadow_world[]; // where the shadow is looked up (lit_cloth.frag)
layout(location = 0) out vec3 out_world[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) out vec2 out_uv[];
layout(location = 3) out vec3 out_shadow_world[];

void main()
{
    out_world[gl_InvocationID] = world[gl_InvocationID];
    out_normal[gl_InvocationID] = world_normal[gl_InvocationID];
    out_uv[gl_InvocationID] = uv[gl_InvocationID];
    out_shadow_world[gl_InvocationID] = shadow_world[gl_InvocationID];
    if (gl_InvocationID == 0) {
        float level = float(SEGMENTS);
        gl_TessLevelOuter[0] = level;
        gl_TessLevelOuter[1] = level;
        gl_TessLevelOuter[2] = level;
        gl_TessLevelInner[0] = level;
    }
}
