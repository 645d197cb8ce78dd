#include "shaders.h"

#include "composite_1x_frag.h"
#include "composite_frag.h"
#include "composite_vert.h"
#include "finalize_comp.h"
#include "lit_cloth_frag.h"
#include "lit_cloth_vert.h"
#include "mesh_comp.h"
#include "pd_gauss_seidel_comp.h"
#include "pd_jacobi_comp.h"
#include "predict_comp.h"
#include "shadow_vert.h"

#define SPIRV(array, file) {array, sizeof array, file}

cvk_spirv cvk_shader(cvk_shader_id id)
{
    static const cvk_spirv table[CVK_SHADER_COUNT] = {
        [CVK_SHADER_PREDICT] = SPIRV(cvk_spv_predict_comp, "predict.comp"),
        [CVK_SHADER_FINALIZE] = SPIRV(cvk_spv_finalize_comp, "finalize.comp"),
        [CVK_SHADER_PD_GAUSS_SEIDEL] = SPIRV(cvk_spv_pd_gauss_seidel_comp, "pd_gauss_seidel.comp"),
        [CVK_SHADER_PD_JACOBI] = SPIRV(cvk_spv_pd_jacobi_comp, "pd_jacobi.comp"),
        [CVK_SHADER_MESH] = SPIRV(cvk_spv_mesh_comp, "mesh.comp"),
        [CVK_SHADER_SHADOW_VERT] = SPIRV(cvk_spv_shadow_vert, "shadow.vert"),
        [CVK_SHADER_LIT_CLOTH_VERT] = SPIRV(cvk_spv_lit_cloth_vert, "lit_cloth.vert"),
        [CVK_SHADER_LIT_CLOTH_FRAG] = SPIRV(cvk_spv_lit_cloth_frag, "lit_cloth.frag"),
        [CVK_SHADER_COMPOSITE_VERT] = SPIRV(cvk_spv_composite_vert, "composite.vert"),
        [CVK_SHADER_COMPOSITE_FRAG] = SPIRV(cvk_spv_composite_frag, "composite.frag"),
        [CVK_SHADER_COMPOSITE_1X_FRAG] = SPIRV(cvk_spv_composite_1x_frag, "composite.frag (one sample)"),
    };
    return table[id];
}
