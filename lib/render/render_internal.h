/* The renderer object, private to the renderer's files (render.c and render_*.c). */
#ifndef CVK_RENDER_INTERNAL_H
#define CVK_RENDER_INTERNAL_H

#include "render/camera.h"
#include "render/mesh.h"
#include "scene/motion.h"
#include "shared/frame.h" /* cvk_frame_uniforms, shared with shaders/render/frame.glsl */

/* The push constants of the lit pass (the Material block of shaders/render/lit_cloth.frag). */
typedef struct cvk_render_material {
    float albedo[4];                 /* rgb: linear colour; w: 1 where the texture replaces it */
    float back[4];                   /* rgb: the back face's colour; w: 1 to use it (else the front's) */
    float fabric[4];                 /* cloths: x: sheen; y: its roughness. Colliders (a
                                        Blinn-Phong highlight): x: its strength; y: its exponent */
    float slab[4];                   /* a thick cloth (the vertex stages read it too): x: how far
                                        this draw moves the vertices along their normals (m, ±
                                        half the thickness for the two faces); y: the thickness
                                        the light through a face crosses (0 for the rim); z: the
                                        normal map's strength (0: none) */
} cvk_render_material;

/* The stages that read the push constants. */
#define CVK_RENDER_PUSH_STAGES (VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT)

/* One collider's triangles in the shared collider buffers, drawn with instance index
   `collider` (the vertex shaders read its pose from the simulation's poses buffer). */
typedef struct cvk_collider_draw {
    uint32_t first_index, index_count;
    uint32_t collider;
    float color[4];                  /* linear RGB, 1 */
    float highlight[2];              /* the Blinn-Phong highlight's strength and exponent */
    bool textured;                   /* material.texture: drawn with rd->textures.collider_set_of */
    bool closed;                     /* a solid seen from outside (sphere, capsule, box): its back
                                        faces are hidden, and the lit pass culls them */
    float repeats;                   /* of the texture per metre: 1 / material.texture_scale */
} cvk_collider_draw;

typedef struct cvk_render_colliders {
    cvk_buffer vertices;             /* 12 floats per vertex: position at rest (m), unit normal,
                                        and both in the collider's texture frame */
    cvk_buffer indices;              /* uint32 */
    cvk_collider_draw* draws;
    uint32_t draw_count;
    cvk_box* boxes;                  /* for the camera: see cvk_view_colliders */
    cvk_view_colliders framing;
    uint32_t ground_texture;         /* 1 + the index of the plane collider that is the ground,
                                        when it has a texture (the composite pass draws it on
                                        the ground); 0: none */
} cvk_render_colliders;

/* The cloths' textures and normal maps and the colliders' textures
   (lib/render/render_textures.c): image 0 is a white stand-in for cloths without a texture,
   image 1 a flat normal for those without a normal map; descriptor set s points at images
   albedo_of_set[s] and normal_of_set[s]. */
typedef struct cvk_render_textures {
    cvk_gpu_image* images;
    uint32_t count;
    uint32_t set_count;
    uint32_t albedo_of_set[CVK_MAX_SETS], normal_of_set[CVK_MAX_SETS];
    uint32_t* set_of;                /* per cloth: its descriptor set, 0 without a texture or
                                        a normal map */
    uint32_t* collider_set_of;       /* per collider: its texture's set, 0 without one */
    VkSampler sampler;
    cvk_buffer uv;                   /* texture coordinates, 2 floats per vertex, then 2 per
                                        rim vertex (render/mesh.h); none when no cloth has a
                                        texture */
} cvk_render_textures;

/* The box the drawn things occupy, found every frame on the device (render_occupied.c). */
typedef struct cvk_render_occupied {
    cvk_buffer box;                  /* 6 uints: low xyz, high xyz, floats' bits made to order */
    uint32_t start[6];               /* the colliders' box, where each frame's box starts */
    cvk_descriptors descriptors;
    VkPipeline pipeline;
    uint32_t groups;
} cvk_render_occupied;

struct cvk_renderer {
    cvk_context* context;
    cvk_mesh* mesh;
    cvk_render_desc desc;
    cvk_view view;
    double gravity[3];               /* the simulation's, for the reach (cvk_view_resolve) */
    /* render.camera_keyframes as two translation-only motions, so the camera follows the
       keyframe rules of lib/scene/motion.c; rd->desc keeps no pointer to the caller's list. */
    cvk_motion eye_path, target_path;
    double* fit_xyz;                 /* render.fit: the points the camera frames, 3 per point */
    uint64_t fit_count;              /* (see cvk_renderer_fit) */
    double seconds;                  /* simulated time of the frames drawn (cvk_renderer_set_time) */
    double overlay_ms;               /* host time of the last frame's overlay; 0 without one */
    VkSampleCountFlagBits samples;
    bool vertex_lit;                 /* render.vertex_lighting holds: the cloths are lit at their
                                        vertices (cvk_render_vertex_lit) */
    float drawn_reach;               /* m the drawn cloth reaches beyond its vertices (Frame.post.y) */

    cvk_gpu_image shadow_map, cloth, cloth_depth, image, stencil;
    cvk_gpu_image occlusion_raw;     /* the ambient occlusion pass's (cvk_render_occlusion_size):
                                        light left, depth along the view */
    cvk_gpu_image occlusion;         /* the same blurred (ao_blur.frag), which the composite reads */
    VkRenderPass shadow_pass, cloth_pass, occlusion_pass, blur_pass, composite_pass;
    VkFramebuffer shadow_framebuffer, cloth_framebuffer, occlusion_framebuffer, blur_framebuffer,
        composite_framebuffer;
    VkSampler shadow_sampler, shadow_depth_sampler, cloth_sampler;
    VkFilter shadow_filter;          /* the shadow map's comparisons: linear where the device
                                        filters its format, else nearest */
    cvk_buffer uniforms;
    cvk_buffer readback;

    VkPipelineLayout pipeline_layout; /* descriptors.pipeline_layout */
    cvk_descriptors descriptors;     /* the one graphics set and its pipeline layout */
    VkDescriptorSet set;
    VkPipeline shadow_pipeline, cloth_pipeline, background_pipeline;
    VkPipeline rect_pipeline;        /* the composite over the occupied rectangle: none unless
                                        cvk_render_rect_drawn */
    VkPipeline footprint_pipeline;   /* the composite over the ground's shadows: none without them */
    VkPipeline collider_shadow_pipeline, collider_pipeline; /* none without colliders to draw */
    VkPipeline collider_closed_pipeline; /* collider_pipeline culling back faces: closed colliders */
    VkPipeline wireframe_pipeline;   /* none without render.wireframe */
    VkPipeline occlusion_pipeline, blur_pipeline; /* none without render.ao */
    VkPipeline slab_pipelines[2];    /* the cloth pass culling back faces (a slab's front face and
                                        its rim), then front faces (its back face): none
                                        without a cloth with a material thickness */
    cvk_render_colliders colliders;
    cvk_render_textures textures;
    cvk_render_occupied occupied;

    VkQueryPool queries;
    cvk_submitter submitter;
    VkCommandBuffer frame_cmd;
};

/* Timestamps of a frame: start, after the mesh, the shadow pass, the cloth pass, the ambient
   occlusion pass, the composite pass and the copy. */
enum { CVK_RENDER_QUERY_COUNT = 7 };

/* The ambient occlusion images' size: half the image's, rounded up (a coarser grid lost the dark
   line along a fold's edge lying on the cloth below it). */
static inline uint32_t cvk_render_half(uint32_t pixels)
{
    return (pixels + 1u) / 2u;
}

/* Whether the composite pass looks the ground's shadows up (over the occupied box's shadow,
   shaders/render/occupied.glsl): with a ground and the key light above it. */
static inline bool cvk_render_footprint_drawn(const cvk_renderer* rd)
{
    return rd->desc.ground && rd->view.key_above_ground;
}

/* Whether it draws the occupied rectangle apart from the rest: with shadows on the ground or
   ambient occlusion. */
static inline bool cvk_render_rect_drawn(const cvk_renderer* rd)
{
    return cvk_render_footprint_drawn(rd) || rd->desc.ao;
}

/* The graphics pipelines: shadow, cloth, background and the occupied rectangle, and with colliders to
   draw the colliders' shadow and lit pipelines. */
cvk_result cvk_renderer_create_pipelines(cvk_renderer* rd, cvk_error* error);

/* The simulation's colliders as triangles (lib/render/render_colliders.c): meshes at rest in one
   vertex and index buffer, one draw per collider, and what the camera frames
   (rd->colliders.framing). Runs before the view is resolved; reads rd->desc and rd->mesh. */
cvk_result cvk_render_colliders_create(cvk_renderer* rd, const double gravity[3], cvk_error* error);
void cvk_render_colliders_destroy(cvk_renderer* rd);

/* A plane collider's texture frame: unit axes x (the scene's x, or z for a plane facing along
   x, less its part along the normal), up (its normal) and z = x × up; a point p is at
   ((p − point)·x, (p − point)·up, (p − point)·z) in it. */
void cvk_render_plane_frame(const cvk_collider_desc* plane, double x[3], double up[3], double z[3]);

/* Records the collider draws; with `colored`, each one's colour as the push constant and its
   texture's descriptor set. The pipeline is bound by the caller. */
void cvk_render_colliders_record(const cvk_renderer* rd, VkCommandBuffer cmd, bool colored);

/* The occupied box (lib/render/render_occupied.c): made after the colliders, recorded after the
   mesh pass and before the passes that read it (its barriers included). */
cvk_result cvk_render_occupied_create(cvk_renderer* rd, cvk_error* error);
void cvk_render_occupied_record(const cvk_renderer* rd, VkCommandBuffer cmd);
void cvk_render_occupied_destroy(cvk_renderer* rd);

/* Binds texture set `set` (rd->descriptors.sets) unless it is bound already (*bound)
   (lib/render/render_frame.c). */
void cvk_render_bind_textures(const cvk_renderer* rd, VkCommandBuffer cmd, uint32_t set, uint32_t* bound);

/* Reads every cloth's and collider's texture (errors name the key path, "cloths.N.texture",
   "colliders.N.material.texture"), makes its mips and uploads them with the cloths' texture
   coordinates; needs rd->mesh. */
cvk_result cvk_render_textures_create(cvk_renderer* rd, cvk_error* error);
void cvk_render_textures_destroy(cvk_renderer* rd);

/* The camera's path (lib/render/render_camera.c): copied from desc's keyframes (rd->desc keeps no
   pointer to them), freed, and the view (rd->view) resolved with the camera where it is at
   `seconds`. Resolving needs rd->mesh, rd->gravity and rd->colliders.framing. */
cvk_result cvk_render_camera_create(cvk_renderer* rd, const cvk_render_desc* desc, cvk_error* error);
void cvk_render_camera_destroy(cvk_renderer* rd);
void cvk_render_camera_resolve(cvk_renderer* rd, double seconds);

/* The frame constants written again from rd->view and rd->desc (lib/render/render.c). */
void cvk_render_write_uniforms(cvk_renderer* rd);

/* render.fit: the points framed become the particles as they are now (read back from the
   device) and the corners of the colliders' boxes. */
cvk_result cvk_render_camera_fit_particles(cvk_renderer* rd, cvk_error* error);

/* The least of `distance` (which changes by at most as much as the eye moves) over where the
   camera's eye is: at `eye`, or with camera keyframes on the straight paths between them
   (sampled, less half the samples' spacing, so never more than the true least). */
double cvk_render_eye_least(const cvk_renderer* rd, const double eye[3],
                            double (*distance)(const double eye[3], const void* to), const void* to);

/* render.vertex_lighting: whether every cloth triangle's longest edge (its rest length, 10 % more
   for stretch) spans at most that many pixels at the nearest the eye comes to the reach (the
   resolved view's eye, or every point of the camera keyframes' path), with no normal map and no
   render.smooth; false with the eye inside the reach. After cvk_render_camera_resolve. */
bool cvk_render_vertex_lit(const cvk_renderer* rd);

/* render.overlay (lib/render/render_overlay.c): "frame N  t = X.XXX s" for rd->seconds drawn
   into the image in the readback buffer, which the last frame has filled. */
void cvk_render_overlay_draw(cvk_renderer* rd);

#endif
