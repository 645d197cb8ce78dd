#include "core/pipelines.h"

#include <stddef.h>

#include "shared/layout.h"

/* The C mirror of every shared block must have the layout GLSL gives it. */
_Static_assert(sizeof(cvk_pd_push) == 52, "cvk_pd_push: 52 bytes in GLSL");
_Static_assert(offsetof(cvk_pd_push, inv_h2) == 16, "cvk_pd_push.inv_h2 at 16");
_Static_assert(offsetof(cvk_pd_push, keep) == 28, "cvk_pd_push.keep at 28");
_Static_assert(offsetof(cvk_pd_push, gravity_h2) == 32, "cvk_pd_push.gravity_h2: a vec4 at 32");
_Static_assert(offsetof(cvk_pd_push, rest_rate) == 48, "cvk_pd_push.rest_rate at 48");
_Static_assert(sizeof(cvk_pd_converge_push) <= sizeof(cvk_pd_push),
               "cvk_pd_converge_push: within the pd layout's push range");
_Static_assert(sizeof(cvk_pd_scalars) == 96, "cvk_pd_scalars: 96 bytes in GLSL");
_Static_assert(offsetof(cvk_pd_scalars, sweep_groups) == 32 &&
                   offsetof(cvk_pd_scalars, copy_groups) == 80,
               "cvk_pd_scalars: the indirect commands where the shaders write them");
_Static_assert(sizeof(cvk_implicit_push) == 48, "cvk_implicit_push: 48 bytes in GLSL");
_Static_assert(offsetof(cvk_implicit_push, gravity) == 32, "cvk_implicit_push.gravity: a vec4 at 32");
_Static_assert(sizeof(cvk_implicit_scalars) == 84, "cvk_implicit_scalars: 84 bytes in GLSL");
_Static_assert(offsetof(cvk_implicit_scalars, reduce_groups) == 48,
               "cvk_implicit_scalars: indirect commands from 48");
_Static_assert(sizeof(cvk_explicit_push) == 48, "cvk_explicit_push: 48 bytes in GLSL");
_Static_assert(offsetof(cvk_explicit_push, gravity) == 32, "cvk_explicit_push.gravity: a vec4 at 32");
_Static_assert(sizeof(cvk_mesh_push) == 12, "cvk_mesh_push: 12 bytes in GLSL");
_Static_assert(offsetof(cvk_mesh_push, triangle_count) == 4, "cvk_mesh_push.triangle_count at 4");
_Static_assert(offsetof(cvk_mesh_push, rim_edge_count) == 8, "cvk_mesh_push.rim_edge_count at 8");
_Static_assert(sizeof(cvk_aero_push) == 48, "cvk_aero_push: 48 bytes in GLSL");
_Static_assert(offsetof(cvk_aero_push, wind) == 16, "cvk_aero_push.wind: a vec4 at 16");
_Static_assert(sizeof(cvk_attach_push) == 16, "cvk_attach_push: 16 bytes in GLSL");
_Static_assert(sizeof(cvk_tear_push) == 16, "cvk_tear_push: 16 bytes in GLSL");
_Static_assert(sizeof(cvk_gpu_attachment) == 16, "cvk_gpu_attachment: 16 bytes in std430");
_Static_assert(sizeof(cvk_gpu_attached) == 32, "cvk_gpu_attached: 32 bytes in std430");
_Static_assert(offsetof(cvk_gpu_attached, particle) == 16, "cvk_gpu_attached.particle at 16");
_Static_assert(sizeof(cvk_gpu_grab) == 32, "cvk_gpu_grab: 32 bytes in std430");
_Static_assert(offsetof(cvk_gpu_grab, particle) == 16, "cvk_gpu_grab.particle at 16");
_Static_assert(sizeof(cvk_grab_push) == 16, "cvk_grab_push: 16 bytes in GLSL");
_Static_assert(sizeof(cvk_gpu_pick) == 32, "cvk_gpu_pick: 32 bytes in std430");
_Static_assert(offsetof(cvk_gpu_pick, position) == 16, "cvk_gpu_pick.position: a vec4 at 16");
_Static_assert(sizeof(cvk_pick_push) == 48, "cvk_pick_push: 48 bytes in GLSL");
_Static_assert(offsetof(cvk_pick_push, radius2) == 32, "cvk_pick_push.radius2 at 32");

typedef struct pipeline_recipe {
    cvk_shader_id shader;
    cvk_spec_recipe spec;
    const char* label;
} pipeline_recipe;

static const pipeline_recipe recipes[CVK_PIPE_COUNT] = {
/* The recipe and label as one list: a recipe CVK_COLLIDER_RUN_PIPELINES passes on arrives
   expanded, its braces' commas splitting it into several arguments. */
#define CVK_PIPE_RECIPE(id, shader, ...) [CVK_PIPE_##id] = {CVK_SHADER_##shader, __VA_ARGS__},
    CVK_PIPELINE_LIST(CVK_PIPE_RECIPE)
#undef CVK_PIPE_RECIPE
};

const char* cvk_pipeline_label(cvk_pipeline_id id)
{
    return id < CVK_PIPE_COUNT ? recipes[id].label : "?";
}

bool cvk_pipeline_streams_particles(cvk_pipeline_id id)
{
    return id < CVK_PIPE_COUNT && recipes[id].spec.count > 0 &&
           recipes[id].spec.source[0] == CVK_SPEC_PARTICLE_WORKGROUP_SIZE;
}

static uint32_t spec_value(cvk_spec_source source, const cvk_spec_inputs* inputs)
{
    if (source >= CVK_SPEC_LITERAL)
        return (uint32_t)(source - CVK_SPEC_LITERAL);
    switch (source) {
    case CVK_SPEC_WORKGROUP_SIZE: return inputs->workgroup_size;
    case CVK_SPEC_PARTICLE_WORKGROUP_SIZE:
        return inputs->particle_workgroup_size ? inputs->particle_workgroup_size
                                               : inputs->workgroup_size;
    case CVK_SPEC_FUSED_WORKGROUP_SIZE:
        return inputs->fused_workgroup_size ? inputs->fused_workgroup_size : inputs->workgroup_size;
    case CVK_SPEC_MAX_DEGREE: return inputs->max_degree;
    case CVK_SPEC_TRUE: return 1;
    case CVK_SPEC_FALSE: return 0;
    case CVK_SPEC_COLLIDER_TYPES: return inputs->collider_types;
    case CVK_SPEC_SELF_CONTACT: return inputs->self_contact ? 1 : 0;
    case CVK_SPEC_WIND: return inputs->wind ? 1 : 0;
    case CVK_SPEC_TETHERS: return inputs->tethers ? 1 : 0;
    case CVK_SPEC_TETHER_SLOTS: return inputs->tether_slots ? inputs->tether_slots : 1;
    case CVK_SPEC_REST: return inputs->rest ? 1 : 0;
    case CVK_SPEC_FUSED_SHARED: return inputs->fused_shared_slots;
    case CVK_SPEC_FUSED_ONE_COPY: return inputs->fused_one_copy ? 1 : 0;
    case CVK_SPEC_LITERAL: break; /* above */
    }
    return 0;
}

cvk_result cvk_pipelines_require(cvk_context* context, cvk_pipelines* p, cvk_pipeline_id id,
                                 VkPipelineLayout layout, const cvk_spec_inputs* inputs,
                                 cvk_error* error)
{
    if (p->pipeline[id])
        return CVK_SUCCESS;
    const pipeline_recipe* recipe = &recipes[id];
    cvk_spec spec = {.count = recipe->spec.count};
    for (uint32_t i = 0; i < spec.count; i++)
        spec.values[i] = spec_value(recipe->spec.source[i], inputs);
    cvk_result r = cvk_cached_compute_pipeline(context, recipe->shader, layout, &spec,
                                               &p->pipeline[id], error);
    if (r != CVK_SUCCESS)
        return r;
    p->layout[id] = layout;
    p->fresh[id] = true;
    return CVK_SUCCESS;
}

/* The pipelines are the context's (cvk_cached_compute_pipeline): the table only forgets them. */
void cvk_pipelines_destroy(cvk_context* context, cvk_pipelines* p)
{
    (void)context;
    *p = (cvk_pipelines){0};
}
