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
    /* Static tables: per triangle two rows (its own, and the one drawn in its place while its
       quad is split along its other diagonal: lib/render/split.h) of its vertices (user order),
       particles (internal order) and the spring along each edge; per vertex its particle
       (| CVK_MESH_HELD where it is never smoothed along a torn border) and the triangles that
       may hold it (slot-major). */
    cvk_buffer triangle_vertices, triangle_particles, triangle_springs, particle_of,
        vertex_triangles;
    VkBufferView view_triangle_vertices, view_triangle_particles, view_triangle_springs,
        view_particle_of, view_vertex_triangles;

    /* The rim of cloths with a material thickness: per edge that is or may become a border
       (one triangle, or a triangle that may tear), a quad of 4 vertices (the vertex layout)
       joining the slab's two faces, collapsed to a point while the edge is not a border; and
       the static index buffer of those quads (6 per edge). rim_edges: 2 uvec4 per edge (its
       ends in user order and half the thickness's bits; the up to 4 triangles that may hold it,
       in either split, UINT32_MAX padded). Without a thick
       cloth, one unused edge so every binding has a buffer, and rim_edge_count 0. */
    uint32_t rim_edge_count;
    uint32_t* rim_ends;          /* host: the 2 vertices (user order) of each rim edge */
    cvk_mesh_range* rims;        /* per cloth: its rim's indices in rim_indices */
    cvk_buffer rim_edges, rim_vertices, rim_indices;
    VkBufferView view_rim_edges;

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
