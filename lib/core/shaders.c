#include "core/shaders.h"

#define CVK_SHADER_LIST_INCLUDE_SPIRV
#include "shader_list.h"

cvk_spirv cvk_shader(cvk_shader_id id)
{
    static const cvk_spirv table[CVK_SHADER_COUNT] = {
#define CVK_SHADER_ENTRY(id, array, label) [CVK_SHADER_##id] = {array, sizeof array, label},
        CVK_SHADER_LIST(CVK_SHADER_ENTRY)
#undef CVK_SHADER_ENTRY
    };
    return table[id];
}
