/* SPIR-V of every shader, compiled by glslang at build time and embedded. */
#ifndef CVK_SHADERS_H
#define CVK_SHADERS_H

#include <stddef.h>
#include <stdint.h>

typedef enum cvk_shader_id {
    CVK_SHADER_PREDICT,
    CVK_SHADER_FINALIZE,
    CVK_SHADER_PD_GAUSS_SEIDEL,
    CVK_SHADER_PD_JACOBI,
    CVK_SHADER_MESH,
    CVK_SHADER_SHADOW_VERT,
    CVK_SHADER_LIT_CLOTH_VERT,
    CVK_SHADER_LIT_CLOTH_FRAG,
    CVK_SHADER_COMPOSITE_VERT,
    CVK_SHADER_COMPOSITE_FRAG,
    CVK_SHADER_COMPOSITE_1X_FRAG,
    CVK_SHADER_COUNT
} cvk_shader_id;

typedef struct cvk_spirv {
    const uint32_t* code;
    size_t bytes;
    const char* name; /* the source file, for messages */
} cvk_spirv;

cvk_spirv cvk_shader(cvk_shader_id id);

#endif
