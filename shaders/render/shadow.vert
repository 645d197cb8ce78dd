#version 450
#extension GL_GOOGLE_include_directive : require
// Shadow pass: the cloth's depth as the key light sees it. Both faces cast; there is no
// fragment shader, and slope-scaled depth bias (pipeline state) keeps lit faces out of their
// own shadow.
#include "render/frame.glsl"

layout(location = 0) in vec3 position;

void main()
{
    gl_Position = frame.light_view_proj * vec4(position, 1.0);
}
