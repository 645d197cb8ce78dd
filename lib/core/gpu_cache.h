/* What a context shares among everything made on it: descriptor set layouts, pipeline layouts
   and compute pipelines, each made once per definition and kept until the context is
   destroyed. A simulation with the dispatch shape and features of one made before on the same
   context (a test's variants, a bench experiment's runs, an application's next level) then
   creates none of its pipelines: on lavapipe, creating them took 2.1 of the 2.5 s that
   creating the 40 × 40 contact drape took (pd_contact.comp's two pipelines 1.6 s), and Mesa's
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

typedef struct cvk_gpu_cache_entry {
    cvk_cached_kind kind;
    uint32_t words;
    uint32_t* key;
    union {
        VkDescriptorSetLayout set_layout;
        VkPipelineLayout pipeline_layout;
        VkPipeline pipeline;
    } object;
} cvk_gpu_cache_entry;

typedef struct cvk_gpu_cache {
    cvk_gpu_cache_entry* entries; /* in the order they were made */
    uint32_t count;
    uint32_t capacity;
} cvk_gpu_cache;

/* Destroys every object in the cache (newest first: a pipeline before its layout, a pipeline
   layout before its set layouts), then the table. */
void cvk_gpu_cache_destroy(VkDevice device, cvk_gpu_cache* cache);
/* The kind of the i-th object made (tests/core/test_gpu_cache.c counts them). */
cvk_cached_kind cvk_gpu_cache_kind(const cvk_gpu_cache* cache, uint32_t i);
/* The object of `kind` made for the key (`words` words), or NULL. */
cvk_gpu_cache_entry* cvk_gpu_cache_find(cvk_gpu_cache* cache, cvk_cached_kind kind,
                                        const uint32_t* key, uint32_t words);
/* A slot for a new object of the key, or NULL when out of host memory: the caller makes the
   object into it, then settles it (made: kept; not made: the slot is given back). */
cvk_gpu_cache_entry* cvk_gpu_cache_reserve(cvk_gpu_cache* cache, cvk_cached_kind kind,
                                           const uint32_t* key, uint32_t words);
void cvk_gpu_cache_settle(cvk_gpu_cache* cache, cvk_gpu_cache_entry* entry, bool made);

#endif
