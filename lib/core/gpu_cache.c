/* The context's shared set layouts, pipeline layouts and compute pipelines (gpu_cache.h): a
   table of definitions, each a few words, searched in order; a context holds tens of them. */
#include "core/gpu_cache.h"

#include <stdlib.h>
#include <string.h>

void cvk_gpu_cache_destroy(VkDevice device, cvk_gpu_cache* cache)
{
    for (uint32_t i = cache->count; i-- > 0;) {
        cvk_gpu_cache_entry* e = &cache->entries[i];
        if (device && e->kind == CVK_CACHED_PIPELINE)
            vkDestroyPipeline(device, e->object.pipeline, NULL);
        else if (device && e->kind == CVK_CACHED_PIPELINE_LAYOUT)
            vkDestroyPipelineLayout(device, e->object.pipeline_layout, NULL);
        else if (device)
            vkDestroyDescriptorSetLayout(device, e->object.set_layout, NULL);
        free(e->key);
    }
    free(cache->entries);
    *cache = (cvk_gpu_cache){0};
}

cvk_cached_kind cvk_gpu_cache_kind(const cvk_gpu_cache* cache, uint32_t i)
{
    return cache->entries[i].kind;
}

cvk_gpu_cache_entry* cvk_gpu_cache_find(cvk_gpu_cache* cache, cvk_cached_kind kind,
                                        const uint32_t* key, uint32_t words)
{
    for (uint32_t i = 0; i < cache->count; i++) {
        cvk_gpu_cache_entry* e = &cache->entries[i];
        if (e->kind == kind && e->words == words &&
            memcmp(e->key, key, words * sizeof(uint32_t)) == 0)
            return e;
    }
    return NULL;
}

cvk_gpu_cache_entry* cvk_gpu_cache_reserve(cvk_gpu_cache* cache, cvk_cached_kind kind,
                                           const uint32_t* key, uint32_t words)
{
    if (cache->count == cache->capacity) {
        uint32_t capacity = cache->capacity ? 2 * cache->capacity : 32;
        cvk_gpu_cache_entry* grown = realloc(cache->entries, capacity * sizeof *grown);
        if (!grown)
            return NULL;
        cache->entries = grown;
        cache->capacity = capacity;
    }
    uint32_t* copy = malloc(words * sizeof *copy);
    if (!copy)
        return NULL;
    memcpy(copy, key, words * sizeof *copy);
    cvk_gpu_cache_entry* e = &cache->entries[cache->count];
    *e = (cvk_gpu_cache_entry){.kind = kind, .words = words, .key = copy};
    return e;
}

void cvk_gpu_cache_settle(cvk_gpu_cache* cache, cvk_gpu_cache_entry* entry, bool made)
{
    if (made) {
        cache->count++;
        return;
    }
    free(entry->key);
    entry->key = NULL;
}

