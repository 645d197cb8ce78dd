#include "sim/memory.h"

#include <stdio.h>
#include <string.h>
#include <sys/resource.h>

#include "core/error.h"
#include "scene/scene.h"

/* Per-particle device bytes, measured with clothvk's Python package (device_peak_bytes of a
   40 x 40 and a 100 x 100 grid, the difference over 8400 particles): 168 with 4 springs per
   particle, 280 with 12 (14 per spring slot over 112), 844 with implicit Euler (+564 at 12
   slots: 3x3 blocks per slot and the CG vectors, 47 per slot; the contact filter added 16
   since). Self-contact, from its buffers' sizes for a grid (two triangles and three edges a
   particle) and the 10000-particle measure of tests/core/test_memory.c (1,490 bytes a
   particle: hanging.json at 100 x 100 with and without it, peak, 2026-11-30; 214 more since
   the edges' ends joined the cell lists, whose pool grew from 14 to 24 entries an edge): the
   hashes of the triangles' centroids and of the edges' midpoints with those points (about
   350), the triangle and edge tables (170), the lists of features, edges and pairs by corner
   (340), the edges' buckets of pairs to list and their counts (396), the edges' ends and cell
   lists (418), the work lists (16), where detection saw each particle and the particle a
   substep before (32). The
   coefficients round each up by about a tenth, so the estimate bounds what is made without
   overstating it by more than a few tens of percent. */
#define DEVICE_BASE 125u
#define DEVICE_PER_SLOT 16u
#define DEVICE_SELF 1854u
#define DEVICE_IMPLICIT_PER_SLOT 52u
/* Explicit integrators, from their buffer sizes (not measured): velocities, the RK2 stage,
   accelerations and the Adams-Bashforth history are 160 bytes, the adjacency 16 per slot;
   rounded up by a tenth. */
#define DEVICE_EXPLICIT 176u
#define DEVICE_EXPLICIT_PER_SLOT 18u
#define DEVICE_CONTACT 64u /* colliders: per-particle contact state */
/* A funnel without self-contact: the triangle tables its edge test reads (16 bytes per
   triangle, about two per particle, and 4 per triangle corner), rounded up. */
#define DEVICE_SHELLS 64u
#define DEVICE_TETHERS 32u /* four pins and four lengths (lib/topology/build.h) */
#define DEVICE_FIXED (64u << 10) /* uniforms, staging, queries: about 10 KB measured */
/* Host bytes per particle beside the device's (resident set of clothvk-sim less its device
   memory on lavapipe, same grids): about 210 with 4 slots, 420 with 12; self-contact about
   +215 more. */
#define HOST_BASE 120u
#define HOST_PER_SLOT 30u
#define HOST_SELF 256u
#define HOST_FIXED (8u << 20)
/* The tethers' search (lib/topology/tether.c) while it runs: labels, lengths, the spring graph. */
#define HOST_TETHERS 200u

static bool any_tethers(const cvk_scene_desc* scene)
{
    for (uint32_t c = 0; c < scene->cloth_count; c++)
        if (scene->cloths[c].tethers > 0.0f)
            return true;
    return false;
}

static uint64_t per_particle_device(const cvk_scene_desc* scene, uint32_t degree)
{
    uint64_t bytes = DEVICE_BASE + (uint64_t)DEVICE_PER_SLOT * degree;
    if (scene->collision.self)
        bytes += DEVICE_SELF;
    else if (cvk_scene_collider_types(scene) & (1u << CVK_COLLIDER_FUNNEL))
        bytes += DEVICE_SHELLS;
    if (scene->collider_count > 0)
        bytes += DEVICE_CONTACT;
    if (any_tethers(scene))
        bytes += DEVICE_TETHERS;
    if (scene->solver.method == CVK_METHOD_IMPLICIT)
        bytes += (uint64_t)DEVICE_IMPLICIT_PER_SLOT * degree;
    if (scene->solver.method == CVK_METHOD_EXPLICIT)
        bytes += DEVICE_EXPLICIT + (uint64_t)DEVICE_EXPLICIT_PER_SLOT * degree;
    return bytes;
}

cvk_memory_estimate cvk_memory_estimate_for(const cvk_scene_desc* scene, uint64_t particles,
                                            uint32_t degree)
{
    uint64_t host = HOST_BASE + (uint64_t)HOST_PER_SLOT * degree;
    if (scene->collision.self)
        host += HOST_SELF;
    if (any_tethers(scene))
        host += HOST_TETHERS;
    /* particles < 2^32 and the per-particle figures < 2^12: no overflow. */
    return (cvk_memory_estimate){
        .device_bytes = DEVICE_FIXED + particles * per_particle_device(scene, degree),
        .host_bytes = HOST_FIXED + particles * host,
    };
}

/* A "Key:   123 kB" line of a /proc file, in bytes; 0 when absent. */
static uint64_t proc_kb(const char* path, const char* key)
{
    FILE* f = fopen(path, "r");
    if (!f)
        return 0;
    char line[256];
    uint64_t value = 0;
    size_t n = strlen(key);
    while (fgets(line, sizeof line, f)) {
        unsigned long long kb;
        if (strncmp(line, key, n) == 0 && sscanf(line + n, " %llu", &kb) == 1) {
            value = (uint64_t)kb * 1024u;
            break;
        }
    }
    fclose(f);
    return value;
}

/* One number in a file (a cgroup's memory.max, memory.current); false for "max" or absent. */
static bool file_number(const char* path, uint64_t* out)
{
    FILE* f = fopen(path, "r");
    if (!f)
        return false;
    unsigned long long v;
    bool ok = fscanf(f, "%llu", &v) == 1;
    fclose(f);
    if (ok)
        *out = (uint64_t)v;
    return ok;
}

static void take_least(uint64_t* room, const char** limit, uint64_t candidate, const char* name)
{
    if (candidate < *room) {
        *room = candidate;
        *limit = name;
    }
}

/* The cgroup limit less usage, where the process's cgroup is the root of the mounted
   hierarchy (containers, systemd scopes mounted privately). */
static void cgroup_room(uint64_t* room, const char** limit)
{
    uint64_t max, used;
    if (file_number("/sys/fs/cgroup/memory.max", &max) &&
        file_number("/sys/fs/cgroup/memory.current", &used))
        take_least(room, limit, max > used ? max - used : 0, "the cgroup's memory.max");
    else if (file_number("/sys/fs/cgroup/memory/memory.limit_in_bytes", &max) &&
             file_number("/sys/fs/cgroup/memory/memory.usage_in_bytes", &used) &&
             max < (1ull << 62))
        take_least(room, limit, max > used ? max - used : 0,
                   "the cgroup's memory.limit_in_bytes");
}

uint64_t cvk_memory_host_room(const char** limit)
{
    uint64_t room = UINT64_MAX;
    const char* name = "none known";
    uint64_t available = proc_kb("/proc/meminfo", "MemAvailable:");
    if (available)
        take_least(&room, &name, available, "MemAvailable");
    cgroup_room(&room, &name);
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        uint64_t size = proc_kb("/proc/self/status", "VmSize:");
        uint64_t cap = (uint64_t)as.rlim_cur;
        take_least(&room, &name, cap > size ? cap - size : 0, "the address-space limit (RLIMIT_AS)");
    }
    if (limit)
        *limit = name;
    return room;
}

/* The largest device-local heap (any heap where the device has none: a CPU device). */
static uint64_t device_heap(const cvk_context* context, bool* host_memory)
{
    const VkPhysicalDeviceMemoryProperties* m = &context->memory;
    uint64_t largest = 0, any = 0;
    for (uint32_t h = 0; h < m->memoryHeapCount; h++) {
        uint64_t size = m->memoryHeaps[h].size;
        any = size > any ? size : any;
        if ((m->memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) && size > largest)
            largest = size;
    }
    *host_memory = context->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    return largest ? largest : any;
}

static double gib(uint64_t bytes)
{
    return (double)bytes / (double)(1u << 30);
}

cvk_result cvk_memory_check(const cvk_context* context, const cvk_scene_desc* scene,
                            const char* where, uint64_t particles, uint32_t degree,
                            cvk_error* error)
{
    cvk_memory_estimate need = cvk_memory_estimate_for(scene, particles, degree);
    bool host_memory = false;
    uint64_t heap = device_heap(context, &host_memory);
    uint64_t held = atomic_load(&context->device_bytes);
    uint64_t device_room = heap > held ? heap - held : 0;
    if (need.device_bytes > device_room)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "%s: %llu particles need about %.2f GiB of device memory; %s has "
                        "%.2f GiB in its largest heap, %.2f GiB of it free to clothvk",
                        where, (unsigned long long)particles, gib(need.device_bytes),
                        context->properties.deviceName, gib(heap), gib(device_room));
    const char* limit = NULL;
    uint64_t host_room = cvk_memory_host_room(&limit);
    uint64_t host_need = need.host_bytes + (host_memory ? need.device_bytes : 0);
    if (host_need > host_room)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "%s: %llu particles need about %.2f GiB of host memory%s; %.2f GiB is "
                        "free (bound by %s)", where, (unsigned long long)particles,
                        gib(host_need),
                        host_memory ? " (the device's memory included: it is the host's)" : "",
                        gib(host_room), limit);
    return CVK_SUCCESS;
}
