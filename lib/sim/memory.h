/* Memory a simulation will need, estimated before anything is built, and the room the host
   and the device have for it (memory.c). A scene that does not fit is refused with
   CVK_ERROR_OUT_OF_MEMORY and both figures, rather than being killed by the kernel's
   out-of-memory killer or a cgroup limit half-way through creation. */
#ifndef CVK_MEMORY_H
#define CVK_MEMORY_H

#include "core/context.h"

typedef struct cvk_memory_estimate {
    uint64_t device_bytes; /* buffers on the device */
    uint64_t host_bytes;   /* the build and the tables on the host, device memory excluded */
} cvk_memory_estimate;

/* Bytes a simulation of `particles` particles with up to `degree` springs each needs, for the
   scene's solver family and collision settings: per-particle coefficients measured on the
   buffers the library makes (see memory.c), rounded up. */
cvk_memory_estimate cvk_memory_estimate_for(const cvk_scene_desc* scene, uint64_t particles,
                                            uint32_t degree);

/* Bytes the host can still give this process: the least of MemAvailable, the cgroup's
   memory limit less its usage (v2 and v1), and the address-space limit (RLIMIT_AS) less the
   process's size. `limit` names the one that bound it. UINT64_MAX where none is known. */
uint64_t cvk_memory_host_room(const char** limit);

/* CVK_ERROR_OUT_OF_MEMORY, with the figures and `where` (the scene key of the size), when the
   estimate exceeds the host's room or the device's largest device-local heap less what the
   context already holds. On a device whose memory is the host's (a CPU device such as
   lavapipe) the device part counts against the host too. */
cvk_result cvk_memory_check(const cvk_context* context, const cvk_scene_desc* scene,
                            const char* where, uint64_t particles, uint32_t degree,
                            cvk_error* error);

#endif
