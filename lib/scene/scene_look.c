/* Validation of how things are drawn: the keys of a cloth's material block beyond color and
   texture, a collider's colour and material, and the renderer's render.fit. */
#include "scene/check.h"
#include "scene/scene.h"

/* material.thickness at most 5 cm: as a float, so a scene's 0.05 passes. */
#define CVK_MAX_THICKNESS 0.05f

bool cvk_look_check(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char material[CVK_KEY_PATH_MAX];
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join(material, base, "material");
    /* Unset (every component below 0) or a colour. */
    bool unset = c->back_color[0] < 0.0f && c->back_color[1] < 0.0f && c->back_color[2] < 0.0f;
    if (!unset && !cvk_check_closed_array(issue, cvk_key_join(path, material, "back_color"), c->back_color, 3, 0.0, 1.0))
        return false;
    if (c->normal_map && c->normal_map[0] == '\0')
        return cvk_issue_at(issue, cvk_key_join(path, material, "normal_map"), "must name an image file, got an "
                            "empty string");
    return cvk_check_closed(issue, cvk_key_join(path, material, "sheen"), c->sheen, 0.0, 1.0) &&
           cvk_check_closed(issue, cvk_key_join(path, material, "normal_strength"), c->normal_strength, 0.0, 2.0) &&
           cvk_check_closed(issue, cvk_key_join(path, material, "roughness"), c->roughness, 0.1, 1.0) &&
           cvk_check_closed(issue, cvk_key_join(path, material, "thickness"), c->thickness, 0.0,
                            (double)CVK_MAX_THICKNESS);
}

/* render.fit: a margin that leaves room for the picture, the direction from a whole eye and
   target, and no keyframed camera (it places itself). */
bool cvk_fit_check(const cvk_render_desc* r, cvk_scene_issue* issue)
{
    if (!r->fit)
        return true;
    if (!cvk_check_closed(issue, "render.fit.margin", r->fit_margin, 0.0, 0.45))
        return false;
    if (r->camera_keyframe_count > 0)
        return cvk_issue_at(issue, "render.fit", "cannot frame a keyframed camera: render.camera_keyframes places "
                            "it (leave one of the two out)");
    if (r->auto_eye != r->auto_target)
        return cvk_issue_at(issue, "render.fit", "takes its view direction from render.eye - render.target: give "
                            "both or neither, got only render.%s", r->auto_eye ? "target" : "eye");
    return true;
}

bool cvk_collider_look_check(const cvk_collider_desc* c, const char* base, cvk_scene_issue* issue)
{
    char path[CVK_KEY_PATH_MAX];
    if (c->texture && c->texture[0] == '\0')
        return cvk_issue_at(issue, cvk_key_join(path, base, "material.texture"), "must name an image file, got an "
                            "empty string");
    return cvk_check_closed_array(issue, cvk_key_join(path, base, "color"), c->color, 3, 0.0, 1.0) &&
           cvk_check_closed(issue, cvk_key_join(path, base, "material.roughness"), c->roughness, 0.1, 1.0) &&
           cvk_check_greater(issue, cvk_key_join(path, base, "material.texture_scale"), c->texture_scale, 0.0);
}
