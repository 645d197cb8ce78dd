/* What a context shares among everything made on it: descriptor set layouts, pipeline layouts
   and compute pipelines, each made once per definition and kept until the context is
   destroyed. A simulation with the dispatch shape and features of one made before on the same
   context (a test's variants, a bench experiment's runs, an application's next level) then
   creates none of its pipelines: on lavapipe they are most of the time creating a contact scene
   takes (docs/performance.md, "Start-up"), and Mesa's
   shader cache does not spare that (lavapipe's VkPipelineCache keeps nothing either). The
   objects belong to the context: whoever gets one from it never destroys it. No lock: what
   makes or destroys anything on a context submits to its queue, which one thread at a time
   may use (docs/library.md, "Context"). */
#ifndef CVK_GPU_CACHE_H
#define CVK_GPU_CACHE_H

#include <stdbool.h>
#include <stdint.h>

#include "clothvk.h"

typedef enum cvk_cached_kind {
    CVK_CACHED_SET_LAYOUT,
    CVK_CACHED_PIPELINE_LAYOUT,
    CVK_CACHED_PIPELINE,
} cvk_cached_kind;

typedef union cvk_cached_object {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout pipeline_layout;
    VkPipeline pipeline;
} cvk_cached_object;

typedef struct cvk_gpu_cache_entry {
    cvk_cached_kind kind;
    uint32_t words;
    uint32_t* key;
    cvk_cached_object object;
} cvk_gpu_cache_entry;

typedef struct cvk_gpu_cache {
    cvk_gpu_cache_entry* entries; /* in the order they were made */
    uint32_t count;
    uint32_t capacity;
} cvk_gpu_cache;

/* Destroys every object in the cache (newest first: a pipeline before its layout, a pipeline
   layout before its set layouts), then the table. */
void cvk_gpu_cache_destroy(VkDevice device, cvk_gpu_cache* cache);
void cvk_gpu_cache_destroy_object(VkDevice device, cvk_cached_kind kind, cvk_cached_object object);
/* The kind of the i-th object made (tests/core/test_gpu_cache.c counts them). */
cvk_cached_kind cvk_gpu_cache_kind(const cvk_gpu_cache* cache, uint32_t i);
/* The object of `kind` made for the key (`words` words), or NULL. */
const cvk_cached_object* cvk_gpu_cache_find(const cvk_gpu_cache* cache, cvk_cached_kind kind,
                                            const uint32_t* key, uint32_t words);
/* Keeps `object` under the key; false when out of host memory (the caller still owns it). */
bool cvk_gpu_cache_add(cvk_gpu_cache* cache, cvk_cached_kind kind, const uint32_t* key,
                       uint32_t words, cvk_cached_object object);

#endif
