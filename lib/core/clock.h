/* Milliseconds of a monotonic clock, for the host-side timings. */
#ifndef CVK_CLOCK_H
#define CVK_CLOCK_H

#include <time.h>

static inline double cvk_now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

#endif
