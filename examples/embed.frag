#version 450
// The application's own shading: a light at the camera, both faces lit.
layout(push_constant) uniform Camera {
    mat4 view_proj;
    vec4 eye;
    vec4 color;
} camera;

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 world_normal;
layout(location = 0) out vec4 color;

void main()
{
    vec3 n = normalize(world_normal);
    vec3 to_eye = normalize(camera.eye.xyz - world);
    float lit = abs(dot(n, to_eye));
    color = vec4(camera.color.rgb * (0.25 + 0.75 * lit), 1.0);
}
