/* Validation of the scene's attachments (kinematic particles moved by keyframes): the pins
   follow the rules of their cloth's pins, the motion those of a collider's. */
#include <inttypes.h>

#include "core/cookie.h"
#include "scene/scene.h"

cvk_cloth_desc cvk_attachment_pins_as_cloth(const cvk_cloth_desc* cloth,
                                            const cvk_attachment_desc* a)
{
    cvk_cloth_desc c = *cloth;
    c.pins = a->pins;
    c.pin_count = a->pin_count;
    c.pin_vertices = a->pin_vertices;
    c.pin_vertex_count = a->pin_vertex_count;
    c.use_pin_box = a->use_pin_box;
    c.pin_box = a->pin_box;
    return c;
}

static bool check_attachment(const cvk_scene_desc* d, uint32_t index, cvk_scene_issue* issue)
{
    const cvk_attachment_desc* a = &d->attachments[index];
    char base[CVK_KEY_PATH_MAX];
    cvk_key_path(base, "attachments.%" PRIu32, index);
    if (a->cookie_ != CVK_COOKIE_ATTACHMENT)
        return cvk_issue_at(issue, base, "attachment description was not made by "
                            "cvk_default_attachment_desc()");
    if (a->cloth >= d->cloth_count) {
        char path[CVK_KEY_PATH_MAX];
        cvk_key_path(path, "%s.cloth", base);
        return cvk_issue_at(issue, path, "must be the index of one of the scene's %" PRIu32
                            " cloths (0 to %" PRIu32 "), got %" PRIu32,
                            d->cloth_count, d->cloth_count - 1, a->cloth);
    }
    if (a->pin_count == 0 && a->pin_vertex_count == 0 && !a->use_pin_box)
        return cvk_issue_at(issue, base, "attaches no particles; give \"pins\" (not empty) or "
                            "\"pin_box\"");
    cvk_cloth_desc pins = cvk_attachment_pins_as_cloth(&d->cloths[a->cloth], a);
    return cvk_check_pins(&pins, base, issue) && cvk_check_pin_box(&pins, base, issue) &&
           cvk_check_motion(&a->motion, base, issue);
}

bool cvk_attachments_solver_check(const cvk_solver_desc* solver, uint32_t attachment_count,
                                  cvk_scene_issue* issue)
{
    if (attachment_count == 0)
        return true;
    if (solver->method == CVK_METHOD_EXPLICIT)
        return cvk_issue_at(issue, "solver.method", "explicit does not move attached particles; "
                            "remove \"attachments\", or use pd or implicit");
    if (solver->linear == CVK_LINEAR_GS_CPU)
        return cvk_issue_at(issue, "solver.linear", "gs-cpu (the host reference) does not move "
                            "attached particles; remove \"attachments\", or use rbgs, jacobi or "
                            "chebyshev");
    return true;
}

bool cvk_attachments_check(const cvk_scene_desc* d, cvk_scene_issue* issue)
{
    if (d->attachment_count > 0 && !d->attachments)
        return cvk_issue_at(issue, "attachments", "is NULL but attachment_count is %" PRIu32,
                            d->attachment_count);
    for (uint32_t i = 0; i < d->attachment_count; i++)
        if (!check_attachment(d, i, issue))
            return false;
    return cvk_attachments_solver_check(&d->solver, d->attachment_count, issue);
}
