/* Size arithmetic that refuses to wrap. Counts in a scene are bounded (lib/scene/scene.h), but the
   sizes made from them are products of several, and one unchecked product that wraps turns
   into a short allocation and a write past its end (substeps = 1431655765 once did). Every
   count × size on the way to an allocation goes through these. */
#ifndef CVK_CHECKED_H
#define CVK_CHECKED_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/* *out = a · b; false when it does not fit. */
static inline bool cvk_mul_size(size_t a, size_t b, size_t* out)
{
    return !__builtin_mul_overflow(a, b, out);
}

static inline bool cvk_mul_u32(uint32_t a, uint32_t b, uint32_t* out)
{
    return !__builtin_mul_overflow(a, b, out);
}

/* malloc of count elements of size bytes (at least one byte); NULL when the product wraps. */
static inline void* cvk_malloc_array(size_t count, size_t size)
{
    size_t bytes;
    if (!cvk_mul_size(count, size, &bytes))
        return NULL;
    return malloc(bytes ? bytes : 1);
}

static inline void* cvk_realloc_array(void* old, size_t count, size_t size)
{
    size_t bytes;
    if (!cvk_mul_size(count, size, &bytes))
        return NULL;
    return realloc(old, bytes ? bytes : 1);
}

#endif
