/* Validation of how a cloth is drawn: the keys of its material block beyond color and texture. */
#include "scene/check.h"
#include "scene/scene.h"

bool cvk_look_check(const cvk_cloth_desc* c, const char* base, cvk_scene_issue* issue)
{
    char material[CVK_KEY_PATH_MAX];
    char path[CVK_KEY_PATH_MAX];
    cvk_key_join(material, base, "material");
    /* Unset (every component below 0) or a colour. */
    bool unset = c->back_color[0] < 0.0f && c->back_color[1] < 0.0f && c->back_color[2] < 0.0f;
    if (!unset && !cvk_check_closed_array(issue, cvk_key_join(path, material, "back_color"), c->back_color, 3, 0.0, 1.0))
        return false;
    return cvk_check_closed(issue, cvk_key_join(path, material, "sheen"), c->sheen, 0.0, 1.0) &&
           cvk_check_closed(issue, cvk_key_join(path, material, "roughness"), c->roughness, 0.1, 1.0);
}
