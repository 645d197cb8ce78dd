/* Temporary: the hash and the distance fields are being written; remove at merge. */
#include "collide.h"
#include "error.h"
cvk_result cvk_hash_create(cvk_context* context, const cvk_hash_desc* desc, cvk_hash* out,
                           cvk_error* error)
{
    (void)context; (void)desc; *out = (cvk_hash){0};
    return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "collision.self: not yet available");
}
void cvk_hash_destroy(cvk_context* context, cvk_hash* hash) { (void)context; (void)hash; }
cvk_result cvk_hash_add_passes(const cvk_hash* hash, cvk_plan* plan, uint32_t count,
                               cvk_error* error)
{ (void)hash; (void)plan; (void)count; (void)error; return CVK_SUCCESS; }
cvk_result cvk_sdf_from_mesh_file(const char* path, const cvk_transform* transform,
                                  uint32_t resolution, float min_voxel, const char* key,
                                  cvk_sdf* out, cvk_error* error)
{
    (void)path; (void)transform; (void)resolution; (void)min_voxel; *out = (cvk_sdf){0};
    return cvk_fail(error, CVK_ERROR_UNSUPPORTED, "%s: mesh colliders not yet available", key);
}
void cvk_sdf_destroy(cvk_sdf* sdf) { (void)sdf; }
float cvk_sdf_sample(const cvk_sdf* sdf, const float p[3]) { (void)sdf; (void)p; return 1e9f; }
