// The constants of a rendered frame, shared by every pass. Mirrors cvk_frame_uniforms in
// lib/render.c (std140: every member is a vec4 or a mat4).
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
    vec4 ground_unlit;     // rgb: the ground's colour without the key light (ambient, fill)
    vec4 ground_key;       // rgb: what the key light adds where nothing shadows it
    vec4 ground_axes[2];   // xyz: along the ground, one checkerboard square long
    vec4 ray_base;         // xyz: the ray through pixel (0, 0), its component along the view 1
    vec4 ray_dx;           // xyz: its change per pixel to the right
    vec4 ray_dy;           // xyz: its change per pixel down
    vec4 fog;              // x, y: depth (along the view) where the ground starts and ends
                           // fading into the background; z: 1 = draw the ground
    vec4 shadow;           // x: texels per side; y: m per texel
    vec4 patch_corners[4]; // xyz: the ground under the shadow map, a quad (strip order)
} frame;
