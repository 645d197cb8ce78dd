/* The constants of a rendered frame, shared by every render pass: declared once for C
   (cvk_frame_uniforms, lib/render/render.c fills it) and GLSL (the Frame block of render/frame.glsl).
   std140: every member is a vec4, an array of vec4 or a mat4, so C's packing is GLSL's. */
#ifndef CVK_SHARED_FRAME_H
#define CVK_SHARED_FRAME_H

#ifdef GL_core_profile
#define CVK_FRAME_MAT4(name) mat4 name;
#define CVK_FRAME_VEC4(name) vec4 name;
#define CVK_FRAME_VEC4S(name, n) vec4 name[n];
#else
#define CVK_FRAME_MAT4(name) float name[16];
#define CVK_FRAME_VEC4(name) float name[4];
#define CVK_FRAME_VEC4S(name, n) float name[n][4];
#endif

#define CVK_FRAME_FIELDS                                                                     \
    CVK_FRAME_MAT4(view_proj)        /* world -> clip space of the camera (depth reversed: 1 at near) */ \
    CVK_FRAME_MAT4(light_view_proj)  /* world -> clip space of the key light's shadow map (0 nearest) */ \
    CVK_FRAME_VEC4(eye)              /* xyz: camera position */                                    \
    CVK_FRAME_VEC4(key_direction)    /* xyz: towards the key light, unit */                        \
    CVK_FRAME_VEC4(key_color)        /* rgb: linear */                                             \
    CVK_FRAME_VEC4(fill_direction)   /* xyz: towards the fill light, unit */                       \
    CVK_FRAME_VEC4(fill_color)                                                                     \
    CVK_FRAME_VEC4(ambient)                                                                        \
    CVK_FRAME_VEC4(background)                                                                     \
    CVK_FRAME_VEC4(ground_color)                                                                   \
    CVK_FRAME_VEC4(ground_plane)     /* xyz: up, the ground's unit normal; w: its height along up */ \
    CVK_FRAME_VEC4(ground_unlit)     /* rgb: the ground's colour without the key light */          \
    CVK_FRAME_VEC4(ground_key)       /* rgb: what the key light adds where nothing shadows it */   \
    CVK_FRAME_VEC4S(ground_axes, 2) /* xyz: along the ground, one checkerboard square long */ \
    CVK_FRAME_VEC4(ray_base)         /* xyz: the ray through pixel (0, 0), along the view 1 */     \
    CVK_FRAME_VEC4(ray_dx)           /* xyz: its change per pixel to the right */                  \
    CVK_FRAME_VEC4(ray_dy)           /* xyz: its change per pixel down */                          \
    CVK_FRAME_VEC4(fog)              /* x, y: view depth where the ground fades; z: 1 = ground */  \
    CVK_FRAME_VEC4(shadow)           /* x: texels per side; y: m per texel */                      \
    CVK_FRAME_VEC4(soft)             /* x: penumbra radius, texels per m of light depth; y: widest \
                                        radius searched, texels; z: m of light depth per unit of   \
                                        map depth; w: 1 = soft shadows */                          \
    CVK_FRAME_VEC4(sky)              /* rgb: light from the sky above; w: 1 = sky and bounce light */ \
    CVK_FRAME_VEC4(bounce)           /* rgb: light the ground sends up */                          \
    CVK_FRAME_VEC4(ao)               /* x: near · far; y: far − near; z: near (depth to distance); \
                                        w: ambient occlusion radius, m */                          \
    CVK_FRAME_VEC4(ao_size)          /* xy: image size, pixels; z: occlusion strength; w: 1 = on */ \
    CVK_FRAME_VEC4(post)             /* x: 1 = highlights rolled off (render.tone_map); y: m the  \
                                        drawn cloth reaches beyond its vertices */                \
    CVK_FRAME_VEC4S(ground_texture, 2) /* the ground's texture coordinates u, v of a point p:     \
                                        dot(xyz, p) + w */

#ifdef GL_core_profile
layout(std140, set = 0, binding = 0) uniform Frame { CVK_FRAME_FIELDS } frame;
#else
#include <stddef.h>
typedef struct cvk_frame_uniforms {
    CVK_FRAME_FIELDS
} cvk_frame_uniforms;
_Static_assert(sizeof(cvk_frame_uniforms) == 2 * 64 + 26 * 16, "Frame: 2 mat4 and 26 vec4");
_Static_assert(offsetof(cvk_frame_uniforms, ray_base) == 128 + 13 * 16, "Frame.ray_base");
_Static_assert(offsetof(cvk_frame_uniforms, ground_texture) == 128 + 24 * 16,
               "Frame.ground_texture");
#endif

#undef CVK_FRAME_MAT4
#undef CVK_FRAME_VEC4
#undef CVK_FRAME_VEC4S

#endif
