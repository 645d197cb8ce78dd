/* An open-addressing map from a 64-bit key to a 32-bit value (linear probing), for tables
   built once on the host: mesh edges and springs by their particle pair. */
#ifndef CVK_U64_MAP_H
#define CVK_U64_MAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CVK_U64_MAP_EMPTY UINT64_MAX /* the one key the map cannot hold */

typedef struct cvk_u64_map {
    uint64_t* key;   /* CVK_U64_MAP_EMPTY where free */
    uint32_t* value;
    size_t mask;     /* slot count − 1, a power of two at least twice the entries */
} cvk_u64_map;

/* Room for `entries` keys; false when memory runs out (free it all the same). */
bool cvk_u64_map_init(cvk_u64_map* map, size_t entries);
void cvk_u64_map_free(cvk_u64_map* map);

/* The slot that holds key, or the free slot where it would go. */
size_t cvk_u64_map_slot(const cvk_u64_map* map, uint64_t key);

/* A well-mixed hash of a 64-bit key (MurmurHash3's finaliser). */
size_t cvk_hash_u64(uint64_t key);

#endif
