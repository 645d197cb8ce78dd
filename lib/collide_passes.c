/* The contact module's passes at the start of each substep: the colliders' poses (and the
   frame state's advance), and for self-contact the hash of the positions and the detection of
   particle–triangle candidates that the solver sweeps then resolve. */
#include <math.h>
#include <stdio.h>

#include "collide.h"
#include "shared/layout.h"
#include "error.h"
#include "sim.h"

/* The longest edge of any cloth triangle at rest. */
static float longest_edge(const cvk_build* b)
{
    float longest = 0.0f;
    for (uint32_t t = 0; t < b->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            const float* p = &b->position[3 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + k]]];
            const float* q =
                &b->position[3 * (size_t)b->internal_of[b->triangles[3 * (size_t)t + (k + 1) % 3]]];
            float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            longest = fmaxf(longest, sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
    return longest;
}

cvk_result cvk_collide_create_detection(cvk_sim* s, cvk_error* error)
{
    cvk_collide* c = &s->collide;
    /* A triangle within the detection radius of p has its lowest corner (its owner) within the
       radius plus the triangle's longest edge; cells that large keep the owner among the 27
       cells around p while the cloth stretches up to 50 %. */
    float cell = CVK_DETECT_RADIUS_THICKNESSES(c->detect_every) * c->thickness +
                 1.5f * longest_edge(&s->build);
    cvk_hash_desc desc = {s->build.particle_count ? s->build.particle_count : 1, cell,
                          &s->positions};
    cvk_result r = cvk_hash_create(s->context, &desc, &c->hash, error);
    if (r != CVK_SUCCESS)
        return r;
    VkDescriptorSetLayout layouts[2] = {c->set_layout, c->hash.set_layout};
    VkPushConstantRange push = {VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(cvk_contact_push)};
    VkPipelineLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 2,
        .pSetLayouts = layouts,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    VkResult vr = vkCreatePipelineLayout(s->context->device, &info, NULL, &c->detect_layout);
    return vr == VK_SUCCESS ? CVK_SUCCESS
                            : cvk_fail_vk(error, "vkCreatePipelineLayout (contact detection)", vr);
}

cvk_result cvk_collide_add_passes(cvk_sim* s, cvk_plan* plan, cvk_error* error)
{
    cvk_collide* c = &s->collide;
    if (!c->colliding)
        return CVK_SUCCESS;
    if (c->collider_count > 0) {
        uint32_t pass = cvk_plan_pass(plan, "colliders");
        cvk_contact_push push = {0, c->collider_count, 0, 0};
        cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_COLLIDER_POSES,
                                       c->descriptors.pipeline_layout, c->set, CVK_DOMAIN_PARTICLES,
                                       0, c->collider_count, &push, sizeof push);
        if (op) {
            op->groups = 1; /* one workgroup: it advances the frame state once */
            snprintf(op->note, sizeof op->note, "poses at t and t + dt, step += 1");
        }
    }
    if (c->self && s->build.free_count > 0) {
        uint32_t first = plan->op_count;
        cvk_result r = cvk_hash_add_passes(&c->hash, plan, s->build.particle_count, error);
        if (r != CVK_SUCCESS)
            return r;
        uint32_t pass = cvk_plan_pass(plan, "contacts");
        cvk_contact_push push = {0, s->build.free_count, 0, 0};
        cvk_op* op = cvk_plan_dispatch(plan, pass, CVK_PIPE_CONTACT_DETECT, c->detect_layout,
                                       c->set, CVK_DOMAIN_PARTICLES, 0, s->build.free_count,
                                       &push, sizeof push);
        if (op) {
            cvk_hash_one_item_each(plan, op); /* lavapipe's loop budget: see hash.h */
            op->set1 = c->hash.set;
            snprintf(op->note, sizeof op->note, "particle-triangle pairs within %.3g m",
                     (double)(CVK_DETECT_RADIUS_THICKNESSES(c->detect_every) * c->thickness));
        }
        for (uint32_t i = first; i < plan->op_count; i++)
            plan->ops[i].every = c->detect_every; /* candidates for the substeps until the next */
    }
    return cvk_plan_check(plan, error);
}
