#version 450
#extension GL_GOOGLE_include_directive : require
// Curved triangles (render.smooth), evaluation stage: PN triangles (Vlachos, Peters, Boyd and
// Mitchell 2001). Each triangle becomes the cubic Bézier patch that passes through its three
// vertices with their normals as its normals there: every edge bulges out along the two end
// normals, so a coarse mesh's outline and shading curve between its vertices instead of turning
// at them. Neighbouring triangles share an edge's control points (they depend on that edge's
// two vertices only), so the curved surface stays closed. The normal is interpolated linearly
// and normalised; texture coordinates linearly.
#include "render/frame.glsl"

// Clockwise in the domain: Vulkan's tessellation domain has its origin at the upper left, so
// this keeps each piece wound as its triangle is (the faces stay front and back).
layout(triangles, equal_spacing, cw) in;

layout(location = 0) in vec3 world_in[];
layout(location = 1) in vec3 normal_in[];
layout(location = 2) in vec2 uv_in[];
layout(location = 3) in vec3 shadow_in[];
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv;
layout(location = 3) out vec3 shadow_world; // the flat triangle's point: where the shadow pass drew it

// The edge control point a third of the way from p towards q, pulled back into p's tangent plane.
vec3 edge_point(vec3 p, vec3 q, vec3 n)
{
    return (2.0 * p + q - dot(q - p, n) * n) / 3.0;
}

void main()
{
    vec3 p1 = world_in[0], p2 = world_in[1], p3 = world_in[2];
    vec3 n1 = normal_in[0], n2 = normal_in[1], n3 = normal_in[2];
    vec3 b210 = edge_point(p1, p2, n1), b120 = edge_point(p2, p1, n2);
    vec3 b021 = edge_point(p2, p3, n2), b012 = edge_point(p3, p2, n3);
    vec3 b102 = edge_point(p3, p1, n3), b201 = edge_point(p1, p3, n1);
    vec3 e = (b210 + b120 + b021 + b012 + b102 + b201) / 6.0;
    vec3 b111 = e + 0.5 * (e - (p1 + p2 + p3) / 3.0);
    float a = gl_TessCoord.x, b = gl_TessCoord.y, c = gl_TessCoord.z;
    world = p1 * (a * a * a) + p2 * (b * b * b) + p3 * (c * c * c) + b210 * (3.0 * a * a * b) +
            b120 * (3.0 * a * b * b) + b201 * (3.0 * a * a * c) + b021 * (3.0 * b * b * c) +
            b102 * (3.0 * a * c * c) + b012 * (3.0 * b * c * c) + b111 * (6.0 * a * b * c);
    vec3 n = a * n1 + b * n2 + c * n3;
    float len = length(n);
    world_normal = len > 0.0 ? n / len : vec3(0.0);
    uv = a * uv_in[0] + b * uv_in[1] + c * uv_in[2];
    shadow_world = a * shadow_in[0] + b * shadow_in[1] + c * shadow_in[2];
    gl_Position = frame.view_proj * vec4(world, 1.0);
}
