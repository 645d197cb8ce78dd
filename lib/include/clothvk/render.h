/* clothvk/render.h — step 5: seeing the cloth. A mesh turns the particles into triangles and
 * normals on the device every frame; draw its buffers with your own pipeline, or let the
 * renderer draw it offscreen and hand you the pixels (cvk_image, cvk_image_write_png).
 */
#ifndef CLOTHVK_RENDER_H
#define CLOTHVK_RENDER_H

#include "sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ----------------------------------------------------------------------------------------
 * Mesh: triangles and vertex normals of the cloths, generated on the device
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_mesh cvk_mesh;

/* Start from cvk_default_mesh_desc() (buffers with only the usage the mesh needs), or pass
   NULL to cvk_mesh_create for the defaults. */
typedef struct cvk_mesh_desc {
    VkBufferUsageFlags vertex_usage; /* usage added to the vertex buffer's (vertex, storage,
                                        transfer source), e.g. for your own compute pass */
    VkBufferUsageFlags index_usage;  /* usage added to the index buffer's (index, storage,
                                        transfer source) */
    uint32_t cookie_;                /* set by cvk_default_mesh_desc; do not touch */
} cvk_mesh_desc;

/* The defaults: no usage added to either buffer. */
CVK_API cvk_mesh_desc cvk_default_mesh_desc(void);

/* Every cloth's triangles, in the vertex and index buffers the mesh owns. desc may be NULL
   (the defaults); otherwise it must come from cvk_default_mesh_desc(): one that did not is
   refused with CVK_ERROR_INVALID_ARGUMENT. The mesh reads the simulation's particles and must
   be destroyed before it. Works on a compute-only queue (drawing is then up to you, on a
   queue that can). */
CVK_API cvk_result cvk_mesh_create(cvk_sim* sim, const cvk_mesh_desc* desc, cvk_mesh** out_mesh,
                                   cvk_error* error);
CVK_API void cvk_mesh_destroy(cvk_mesh* mesh);

/* The triangles of one cloth: a range of the index buffer, for one draw call. */
typedef struct cvk_mesh_range {
    uint32_t first_index;
    uint32_t index_count;        /* 3 per triangle: 6 (grid[0] − 1)(grid[1] − 1) for a grid */
} cvk_mesh_range;

/* What to bind to draw the mesh. The buffers live until cvk_mesh_destroy. */
typedef struct cvk_mesh_buffers {
    VkBuffer vertex_buffer;      /* one vertex per particle, in the order of
                                    cvk_sim_read_positions */
    uint32_t vertex_count;
    uint32_t vertex_stride;      /* bytes from one vertex to the next: 32 */
    uint32_t position_offset;    /* 0: position, 3 floats (VK_FORMAT_R32G32B32_SFLOAT), m; a 4th
                                    float, 1, follows */
    uint32_t normal_offset;      /* 16: unit normal, 3 floats, on the side the triangles wind
                                    counter-clockwise (a grid: u_axis × v_axis);
                                    zero at a vertex with no triangle; a 4th float, 0, follows */
    VkBuffer index_buffer;       /* triangle lists; a triangle whose constraints are gone (torn)
                                    has three equal indices, so it draws nothing */
    VkIndexType index_type;      /* VK_INDEX_TYPE_UINT32 */
    uint32_t index_count;        /* all cloths */
    uint32_t cloth_count;
    const cvk_mesh_range* cloths; /* one range per cloth, in scene order; owned by the mesh */
} cvk_mesh_buffers;

CVK_API cvk_mesh_buffers cvk_mesh_get_buffers(const cvk_mesh* mesh);

/* Records the mesh generation — one compute dispatch that writes every vertex (position and
   area-weighted normal) and every triangle from the current particles — into `cmd`, which is
   recording, outside a render pass, from a pool of the context's queue family. Nothing is
   submitted and nothing waits; record it after cvk_sim_record in the same command buffer (or
   a later submission) and before your draw.

   Synchronisation contract (the VkFFT model: the library records its own barriers, you record
   the one into your stage):
   - The library begins with one barrier from COMPUTE_SHADER (shader writes: the simulation's
     positions) and, on a queue with graphics, VERTEX_INPUT (your earlier draws from these
     buffers, a write-after-read hazard) to COMPUTE_SHADER (shader reads and writes).
   - Its compute shader writes the vertex and index buffers (VK_ACCESS_SHADER_WRITE_BIT). It
     binds its own compute pipeline, descriptor set and push constants: compute state you bound
     before is lost. It ends without a trailing barrier.
   - Before you draw, record a barrier from VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT /
     VK_ACCESS_SHADER_WRITE_BIT to VK_PIPELINE_STAGE_VERTEX_INPUT_BIT /
     VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT (or to whatever stage
     reads the buffers).
   - If a stage other than vertex input or a compute shader reads the buffers, make it finish
     before the next cvk_mesh_record (an execution barrier from that stage to
     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT). */
CVK_API cvk_result cvk_mesh_record(cvk_mesh* mesh, VkCommandBuffer cmd, cvk_error* error);

/* ----------------------------------------------------------------------------------------
 * Renderer: offscreen images of the mesh, shadow-mapped, no window system
 * ------------------------------------------------------------------------------------- */

typedef struct cvk_renderer cvk_renderer;

/* Draws `mesh` as its render description says (usually &scene->render): a shadow pass from
   the key light into a depth map, then the lit pass — the cloth lit, shadowed and
   multisampled, then resolved in linear light over the ground and sky (one sample per pixel:
   they have no edges to smooth) into an sRGB image — copied into a host-visible buffer.
   Needs a queue family with graphics: on a compute-only queue it fails with
   CVK_ERROR_UNSUPPORTED. Fails with CVK_ERROR_DEVICE_LIMIT when the image, the shadow map or
   the sample count is more than the device allows. desc is copied; the mesh must outlive the
   renderer. Everything is created here, pipelines compiled and one frame drawn: no frame
   creates anything. desc must come from cvk_default_render_desc() (a scene's render does):
   one that did not is refused with CVK_ERROR_INVALID_ARGUMENT, as is NULL. */
CVK_API cvk_result cvk_renderer_create(cvk_mesh* mesh, const cvk_render_desc* desc,
                                       cvk_renderer** out_renderer, cvk_error* error);
CVK_API void cvk_renderer_destroy(cvk_renderer* renderer);

/* Records one frame into `cmd` (recording, outside a render pass, from a pool of the
   context's queue family): the mesh generation (cvk_mesh_record and its barrier), a barrier
   from the compute shader to vertex input, the shadow pass, the lit pass, a copy of the image
   into the renderer's host-visible buffer and a barrier from that copy to HOST reads (so do
   not record cvk_mesh_record for it yourself). Record it after cvk_sim_record to draw the
   frame just simulated. The renderer's images, buffers and
   timestamp queries are its own; the render passes order every access to them, frame after
   frame. One submission of a renderer's frame may be in flight at a time. Graphics and compute
   state you bound before the call is lost. In a scene with colliders (drawn where the
   simulation's own buffer says they are) it ends with an execution barrier from the vertex
   shader to compute shaders, so the next recorded simulation frame does not move them while
   they are drawn. */
CVK_API cvk_result cvk_renderer_record(cvk_renderer* renderer, VkCommandBuffer cmd, cvk_error* error);

/* Draws one frame of the current particles and waits: a command buffer recorded once, one
   submission, one host wait; then, with render.overlay, the frame number and time (those of
   cvk_renderer_set_time) are drawn into the read-back image on the host. A frame recorded with
   cvk_renderer_record has no overlay. */
CVK_API cvk_result cvk_renderer_draw(cvk_renderer* renderer, cvk_error* error);

/* Pixels in memory: RGBA, 8 bits per channel, sRGB-encoded, rows top to bottom. */
typedef struct cvk_image {
    const uint8_t* pixels;
    uint32_t width, height;
    uint32_t row_bytes;          /* bytes from one row to the next, at least 4 · width */
} cvk_image;

/* The last frame drawn, in the renderer's host-visible buffer: valid until the next
   submission of one of its frames (read it after cvk_renderer_draw returns, or after the
   submission you recorded with cvk_renderer_record has completed). Alpha is 255. */
CVK_API cvk_image cvk_renderer_get_image(const cvk_renderer* renderer);

/* Device time of the last completed frame, per pass; < 0 where not measured. */
typedef struct cvk_render_timing {
    double mesh_ms;              /* mesh generation */
    double shadow_ms;            /* shadow pass */
    double lit_ms;               /* lit pass: the multisampled cloth, then its resolve over the
                                    ground and sky */
    double readback_ms;          /* copy of the image into the host-visible buffer */
    double total_ms;
    double ao_ms;                /* ambient occlusion pass (0 without render.ao); not in lit_ms */
    double overlay_ms;           /* host time of render.overlay's text, drawn into the read-back
                                    image by cvk_renderer_draw (0 without it) */
    double composite_ms;         /* the part of lit_ms after the cloth: the ground, the sky and
                                    the resolve */
} cvk_render_timing;

CVK_API cvk_render_timing cvk_renderer_get_timing(const cvk_renderer* renderer);

/* Where the camera ended up once the automatic placement was done. */
typedef struct cvk_render_view {
    float eye[3], target[3], up[3];
    float fov_y;                 /* degrees */
    float view_proj[16];         /* world -> Vulkan clip space, column-major (x right, y down,
                                    depth 1 at the near plane and 0 at the far one) */
    float ground_height;         /* m along up */
    float reach_min[3], reach_max[3]; /* the box the camera frames: where the cloths can go */
} cvk_render_view;

CVK_API cvk_render_view cvk_renderer_get_view(const cvk_renderer* renderer);

/* Moves a camera with keyframes (render.camera_keyframes) to where it is at `seconds` of
   simulated time, for the frames drawn from now on (a renderer starts at time 0); without
   keyframes it does nothing. Call it while no frame of the renderer is in flight. */
CVK_API void cvk_renderer_set_time(cvk_renderer* renderer, double seconds);

/* With render.fit: frames the corners of the box lo..hi (m) together with those of the finite
   colliders' boxes (each at rest and at each keyframe) for the frames drawn from now on, from
   the same direction; lo and hi NULL frame the particles themselves as they are now (read
   back from the device, a wait), as cvk_renderer_create does. For an image sequence pass the union of every frame's box, so the
   camera holds still. Without render.fit, CVK_ERROR_INVALID_ARGUMENT. Call it while no frame
   of the renderer is in flight. */
CVK_API cvk_result cvk_renderer_fit(cvk_renderer* renderer, const float lo[3], const float hi[3],
                                   cvk_error* error);

/* Writes an image as a PNG file: to a temporary name in the same folder, then renamed, so the
   file is complete or absent; a path that exists and is not a regular file (a device, FIFO,
   folder or link) is refused with CVK_ERROR_IO rather than replaced. An opaque image (every
   alpha 255) is written as RGB.
   Compression is fast (zlib level 2), not smallest. */
CVK_API cvk_result cvk_image_write_png(const cvk_image* image, const char* path, cvk_error* error);

#ifdef __cplusplus
}
#endif
#endif /* CLOTHVK_RENDER_H */
