#version 450
// The application's own vertex shader: it reads clothvk's vertex buffer as documented in
// cvk_mesh_buffers (position at offset 0, normal at offset 16, 32-byte stride).
layout(push_constant) uniform Camera {
    mat4 view_proj;
    vec4 eye;
    vec4 color;
} camera;

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 0) out vec3 world;
layout(location = 1) out vec3 world_normal;

void main()
{
    world = position;
    world_normal = normal;
    gl_Position = camera.view_proj * vec4(position, 1.0);
}
