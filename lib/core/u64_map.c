#include "core/u64_map.h"

#include <stdlib.h>
#include <string.h>

size_t cvk_hash_u64(uint64_t k)
{
    k ^= k >> 33;
    k *= UINT64_C(0xff51afd7ed558ccd);
    k ^= k >> 33;
    k *= UINT64_C(0xc4ceb9fe1a85ec53);
    k ^= k >> 33;
    return (size_t)k;
}

bool cvk_u64_map_init(cvk_u64_map* m, size_t entries)
{
    size_t slots = 16;
    while (slots < 2 * entries)
        slots *= 2;
    m->key = malloc(slots * sizeof *m->key);
    m->value = malloc(slots * sizeof *m->value);
    m->mask = slots - 1;
    if (!m->key || !m->value)
        return false;
    memset(m->key, 0xff, slots * sizeof *m->key);
    return true;
}

void cvk_u64_map_free(cvk_u64_map* m)
{
    free(m->key);
    free(m->value);
    m->key = NULL;
    m->value = NULL;
}

size_t cvk_u64_map_slot(const cvk_u64_map* m, uint64_t key)
{
    size_t i = cvk_hash_u64(key) & m->mask;
    while (m->key[i] != key && m->key[i] != CVK_U64_MAP_EMPTY)
        i = (i + 1) & m->mask;
    return i;
}
