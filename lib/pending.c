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
