/* The mesh object; private so the renderer can reach its buffers and its simulation. */
#ifndef CVK_MESH_H
#define CVK_MESH_H

#include "core/gpu.h"
#include "sim/sim.h"

#include "shared/layout.h" /* cvk_mesh_push, shared with shaders/render/mesh.comp */

struct cvk_mesh {
    cvk_sim* sim;
    cvk_context* context;
    uint32_t vertex_count;
    uint32_t triangle_count;
    uint32_t max_adjacent;       /* triangles around one vertex, at most */
    cvk_mesh_range* cloths;

    cvk_buffer vertices, indices;
    /* Static tables: per triangle its vertices (user order), particles (internal order) and
       the spring along each edge; per vertex its particle and its triangles (slot-major). */
    cvk_buffer triangle_vertices, triangle_particles, triangle_springs, particle_of,
        vertex_triangles;
    VkBufferView view_triangle_vertices, view_triangle_particles, view_triangle_springs,
        view_particle_of, view_vertex_triangles;

    VkDescriptorSetLayout set_layout;
    VkPipelineLayout pipeline_layout;
    VkDescriptorPool descriptor_pool;
    VkDescriptorSet set;
    VkPipeline pipeline;
    uint32_t groups;
    bool graphics_queue;         /* the leading barrier also waits for vertex input */
    cvk_submitter submitter;
};

#endif
