/* The renderer object, private to render.c and render_pipelines.c. */
#ifndef CVK_RENDER_INTERNAL_H
#define CVK_RENDER_INTERNAL_H

#include "camera.h"
#include "mesh.h"
#include "shared/frame.h" /* cvk_frame_uniforms, shared with shaders/frame.glsl */

struct cvk_renderer {
    cvk_context* context;
    cvk_mesh* mesh;
    cvk_render_desc desc;
    cvk_view view;
    VkSampleCountFlagBits samples;

    cvk_gpu_image shadow_map, cloth, cloth_depth, image, stencil;
    VkRenderPass shadow_pass, cloth_pass, composite_pass;
    VkFramebuffer shadow_framebuffer, cloth_framebuffer, composite_framebuffer;
    VkSampler shadow_sampler, cloth_sampler;
    cvk_buffer uniforms;
    cvk_buffer readback;

    VkPipelineLayout pipeline_layout; /* descriptors.pipeline_layout */
    cvk_descriptors descriptors;     /* the one graphics set and its pipeline layout */
    VkDescriptorSet set;
    VkPipeline shadow_pipeline, cloth_pipeline, background_pipeline, patch_pipeline;

    VkQueryPool queries;
    cvk_submitter submitter;
    VkCommandBuffer frame_cmd;
};

/* The four graphics pipelines: shadow, cloth, background and ground patch. */
cvk_result cvk_renderer_create_pipelines(cvk_renderer* rd, cvk_error* error);

#endif
