// The constants of a rendered frame, shared by the shadow and lit passes. Mirrors
// cvk_frame_uniforms in lib/render.c (std140: every member is a vec4 or a mat4).
layout(std140, set = 0, binding = 0) uniform Frame {
    mat4 view_proj;        // world -> clip space of the camera (depth reversed: 1 at near)
    mat4 light_view_proj;  // world -> clip space of the key light's shadow map (0 nearest)
    vec4 eye;              // xyz: camera position
    vec4 key_direction;    // xyz: towards the key light, unit
    vec4 key_color;        // rgb: linear
    vec4 fill_direction;   // xyz: towards the fill light, unit
    vec4 fill_color;
    vec4 ambient;
    vec4 background;
    vec4 ground_color;
    vec4 ground_plane;     // xyz: up, the ground's unit normal; w: its height along up
    vec4 ground_center;    // xyz: under the target; w: radius at which it has faded out
    vec4 shadow;           // x: texels per side; y: m per texel
} frame;
