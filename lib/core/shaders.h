/* SPIR-V of every shader, compiled by glslang at build time and embedded. The ids come from
   the one list in shaders/meson.build (CVK_SHADER_<NAME> for each entry). */
#ifndef CVK_SHADERS_H
#define CVK_SHADERS_H

#include <stddef.h>
#include <stdint.h>

#include "shader_list.h"

typedef enum cvk_shader_id {
#define CVK_SHADER_ID(id, array, label) CVK_SHADER_##id,
    CVK_SHADER_LIST(CVK_SHADER_ID)
#undef CVK_SHADER_ID
    CVK_SHADER_COUNT
} cvk_shader_id;

typedef struct cvk_spirv {
    const uint32_t* code;
    size_t bytes;
    const char* name; /* the source file, for messages */
} cvk_spirv;

cvk_spirv cvk_shader(cvk_shader_id id);

#endif
