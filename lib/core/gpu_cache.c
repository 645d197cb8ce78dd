/* The context's shared set layouts, pipeline layouts and compute pipelines (gpu_cache.h): a
   table of definitions, each a few words, searched in order; a context holds tens of them. */
#include "core/gpu_cache.h"

#include <stdlib.h>
#include <string.h>

void cvk_gpu_cache_destroy_object(VkDevice device, cvk_cached_kind kind, cvk_cached_object object)
{
    if (kind == CVK_CACHED_PIPELINE)
        vkDestroyPipeline(device, object.pipeline, NULL);
    else if (kind == CVK_CACHED_PIPELINE_LAYOUT)
        vkDestroyPipelineLayout(device, object.pipeline_layout, NULL);
    else
        vkDestroyDescriptorSetLayout(device, object.set_layout, NULL);
}

void cvk_gpu_cache_destroy(VkDevice device, cvk_gpu_cache* cache)
{
    for (uint32_t i = cache->count; i-- > 0;) {
        if (device)
            cvk_gpu_cache_destroy_object(device, cache->entries[i].kind, cache->entries[i].object);
        free(cache->entries[i].key);
    }
    free(cache->entries);
    *cache = (cvk_gpu_cache){0};
}

cvk_cached_kind cvk_gpu_cache_kind(const cvk_gpu_cache* cache, uint32_t i)
{
    return cache->entries[i].kind;
}

const cvk_cached_object* cvk_gpu_cache_find(const cvk_gpu_cache* cache, cvk_cached_kind kind,
                                            const uint32_t* key, uint32_t words)
{
    for (uint32_t i = 0; i < cache->count; i++) {
        const cvk_gpu_cache_entry* e = &cache->entries[i];
        if (e->kind == kind && e->words == words &&
            memcmp(e->key, key, words * sizeof(uint32_t)) == 0)
            return &e->object;
    }
    return NULL;
}

bool cvk_gpu_cache_add(cvk_gpu_cache* cache, cvk_cached_kind kind, const uint32_t* key,
                       uint32_t words, cvk_cached_object object)
{
    if (cache->count == cache->capacity) {
        uint32_t capacity = cache->capacity ? 2 * cache->capacity : 32;
        cvk_gpu_cache_entry* grown = realloc(cache->entries, capacity * sizeof *grown);
        if (!grown)
            return false;
        cache->entries = grown;
        cache->capacity = capacity;
    }
    uint32_t* copy = malloc(words * sizeof *copy);
    if (!copy)
        return false;
    memcpy(copy, key, words * sizeof *copy);
    cache->entries[cache->count++] =
        (cvk_gpu_cache_entry){.kind = kind, .words = words, .key = copy, .object = object};
    return true;
}
