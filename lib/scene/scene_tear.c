/* Validation of tearing: a cloth's "tearing" block, and tearing apart from tethers (every
   solver tears). */
#include "scene/scene.h"

bool cvk_scene_tears(const cvk_scene_desc* d)
{
    for (uint32_t i = 0; i < d->cloth_count; i++)
        if (d->cloths[i].tearing.max_stretch > 0.0f)
            return true;
    return false;
}

/* A tether holds a particle near its pins along paths of the whole cloth: once the cloth
   tears, it would pull a torn-off piece back towards pins it no longer hangs from. */
static bool check_cloth(const cvk_cloth_desc* c, uint32_t index, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    cvk_key_path(path, "cloths.%u.tearing.max_stretch", index);
    float v = c->tearing.max_stretch;
    if (!cvk_check_at_least(issue, path, v, 0.0))
        return false;
    if (v > CVK_MAX_TEAR_STRETCH)
        return cvk_issue_at(issue, path, "must be at most %g (a spring %g times its rest length "
                            "is a diverged solve), got %s", CVK_MAX_TEAR_STRETCH,
                            CVK_MAX_TEAR_STRETCH + 1.0, cvk_float_text(v).text);
    if (v > 0.0f && c->tethers != 0.0f) {
        cvk_key_path(path, "cloths.%u.tearing", index);
        return cvk_issue_at(issue, path, "a cloth with tethers cannot tear (a tether would pull "
                            "a torn-off piece back towards its pins); remove \"tethers\" or "
                            "\"tearing\"");
    }
    return true;
}

bool cvk_tearing_check(const cvk_scene_desc* d, cvk_scene_issue* issue)
{
    for (uint32_t i = 0; i < d->cloth_count; i++)
        if (!check_cloth(&d->cloths[i], i, issue))
            return false;
    return true;
}
