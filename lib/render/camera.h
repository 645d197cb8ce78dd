/* Where the camera, the key light's shadow frustum and the ground go: resolved once, on the
   host, from the render description and the scene's reach. */
#ifndef CVK_CAMERA_H
#define CVK_CAMERA_H

#include "topology/build.h"

typedef struct cvk_box {
    double lo[3], hi[3];
} cvk_box;

typedef struct cvk_view {
    double eye[3], target[3], up[3];   /* up: unit, the ground's normal */
    double fov_y;                      /* degrees */
    double width, height;              /* image size, pixels */
    double aspect;                     /* width / height */
    double near, far;                  /* m, along the view direction */
    float view_proj[16];               /* world -> Vulkan clip space, column-major, depth 1 at
                                          near and 0 at far (reversed for float precision) */
    double ray_base[3];                /* the ray through the corner of pixel (0, 0), with a
                                          component of 1 along the view direction */
    double ray_dx[3], ray_dy[3];       /* its change per pixel right and down */
    float light_view_proj[16];         /* world -> the key light's orthographic clip space, depth
                                          0 nearest the light */
    double key_direction[3];           /* unit, towards the key light */
    double fill_direction[3];          /* unit, towards the fill light */
    double shadow_texel;               /* m covered by one shadow-map texel */
    double shadow_depth;               /* m of light depth from 0 to 1 in the shadow map */
    double ground_height;              /* m along up */
    double ground_tile;                /* side of the ground's checkerboard squares, m */
    double ground_axes[2][3];          /* along the ground, 1 / ground_tile long: checker space */
    double fog_start, fog_end;         /* depth along the view where the ground fades into the
                                          background, m */
    bool key_above_ground;             /* the key light is above the ground */
    cvk_box reach;                     /* where the cloths can go, and the colliders near them */
} cvk_view;

/* What the colliders add to the view. A collider near the cloths is framed with them; one far
   away, or the part of a huge one beyond the cloths' neighbourhood, is not (a 100 m plane or a
   distant box does not zoom the camera out). */
typedef struct cvk_view_colliders {
    const cvk_box* boxes;              /* where finite colliders are drawn: each at rest and at
                                          each keyframe */
    uint32_t box_count;
    cvk_box drawn;                     /* everything drawn for colliders (empty: lo > hi): the
                                          depth range holds it */
    bool ground_plane;                 /* a static plane collider facing up is the ground */
    double ground_plane_height;        /* m along up: its height (the highest such plane) */
} cvk_view_colliders;

/* The box the cloths can occupy: their starting box and, when gravity moves them, for a
   pinned cloth every point within 1.35 times its rest distance of each of its pins (the
   margin covers the stretch of a hanging cloth), no higher than it starts. gravity is zero
   when nothing falls (no integration or no gravity). */
void cvk_reach_box(const cvk_build* build, const double gravity[3], cvk_box* out);

/* An empty box (lo = +inf, hi = -inf) and a point added to one. */
void cvk_box_empty(cvk_box* box);
void cvk_box_add(cvk_box* box, const double p[3]);

/* Fills everything above. The description must have passed validation. colliders may be NULL
   (none): the view is then exactly the cloths'. fit, with desc->fit, holds the points to
   frame in place of the reach (the ground stays where the reach puts it; the reach becomes
   their box): the camera looks at the middle of their picture along eye − target (both
   given) or the default direction, as near as keeps desc->fit_margin of the image free on
   each side; NULL (or no points) frames the reach. */
typedef struct cvk_view_fit {
    const double* xyz;                 /* 3 per point, m */
    uint64_t count;
} cvk_view_fit;

void cvk_view_resolve(const cvk_render_desc* desc, const cvk_build* build, const double gravity[3],
                      const cvk_view_colliders* colliders, const cvk_view_fit* fit, uint32_t shadow_map_size,
                      cvk_view* out);

#endif
