/* The collision block: its checks (a radius against the thickness here when both are given,
   in cvk_collision_radius_check once the simulation has resolved a default thickness), the
   radius it resolves to, and the notes for the keys of an earlier contact that have no
   effect. */
#include "scene/scene.h"

/* m: a thickness or a radius above this is a typo (a cloth contact a metre thick). */
#define MAX_CONTACT_DISTANCE 1.0
/* Substeps: a detection held back longer leaves the cloth held at its bounds for most of a
   frame. */
#define MAX_DETECTION_INTERVAL 64u

static bool check_distance(cvk_scene_issue* issue, const char* path, float v)
{
    if (!cvk_check_at_least(issue, path, v, 0.0))
        return false;
    return v <= MAX_CONTACT_DISTANCE ||
           cvk_issue_at(issue, path, "must be at most %g m, got %s", MAX_CONTACT_DISTANCE, cvk_float_text(v).text);
}

bool cvk_collision_check(const cvk_collision_desc* c, cvk_scene_issue* issue)
{
    if (!check_distance(issue, "collision.thickness", c->thickness) ||
        !check_distance(issue, "collision.radius", c->radius) ||
        !cvk_check_at_least(issue, "collision.friction", c->friction, 0.0) ||
        !cvk_check_finite(issue, "collision.static_friction", c->static_friction))
        return false;
    if (c->detection_interval > MAX_DETECTION_INTERVAL)
        return cvk_issue_at(issue, "collision.detection_interval",
                            "must be at most %u substeps, got %u", MAX_DETECTION_INTERVAL,
                            c->detection_interval);
    if (c->static_friction < c->friction)
        return cvk_issue_at(issue, "collision.static_friction", "must be at least friction (%s), got %s",
                            cvk_float_text(c->friction).text, cvk_float_text(c->static_friction).text);
    /* A default thickness is known only from the build: checked then. */
    if (c->thickness > 0.0f)
        return cvk_collision_radius_check(c, c->thickness, issue);
    return true;
}

bool cvk_collision_radius_check(const cvk_collision_desc* c, float thickness, cvk_scene_issue* issue)
{
    if (c->radius == 0.0f || c->radius > thickness)
        return true;
    return cvk_issue_at(issue, "collision.radius",
                        "%g is not more than the thickness %g%s (contact acts between the "
                        "thickness and the radius)", c->radius, thickness,
                        c->thickness > 0.0f ? "" : ", half the shortest structural rest length");
}

float cvk_collision_radius(const cvk_collision_desc* c, float thickness)
{
    return c->radius > 0.0f ? c->radius : CVK_RADIUS_THICKNESSES * thickness;
}

uint32_t cvk_collision_detection_interval(const cvk_collision_desc* c)
{
    return c->detection_interval > 1 ? c->detection_interval : 1u;
}

uint32_t cvk_collision_notes(const cvk_collision_desc* c, const char* notes[CVK_COLLISION_NOTES_MAX])
{
    uint32_t n = 0;
    if (c->detect_every != 0)
        notes[n++] = "collision.detect_every has no effect: contact searches again when a "
                     "particle's displacement reaches its bound";
    if (c->exclusion != 0.0f)
        notes[n++] = "collision.exclusion has no effect: no pair of cloth primitives that shares "
                     "no particle is left out of contact";
    if (c->edges)
        notes[n++] = "collision.edges has no effect: edge-edge contact is always on";
    return n;
}
