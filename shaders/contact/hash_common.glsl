// The spatial hash (lib/contact/hash.h): its descriptor set and the queries a shader makes of it.
//
// An including shader picks the set index with `#define HASH_SET n` before the include
// (default 0) and declares its own workgroup size and push data; the hash's parameters come
// from a buffer of the set. The build passes (hash_*.comp) define HASH_BUILD first and get
// their push block and helpers too.
//
// A query visits the 27 cells around a point. Two cells can share a slot, so an entry of a
// visited slot counts only when its own cell is the one visited:
//
//     ivec3 home = hash_cell(x);
//     for (uint n = 0u; n < 27u; n++) {
//         ivec3 cell = hash_neighbour_cell(home, n);
//         uvec2 range = hash_range(cell);
//         for (uint e = range.x; e < range.y; e++) {
//             uint q = hash_entry_point(e).w;
//             if (!hash_in_cell(q, cell))
//                 continue;
//             ... point q, at hash_point(q), in the order the build's atomics took them ...
//         }
//     }
//
// Every point within one cell size of x is found this way, each once. On SIMD hardware the
// nested loops run, at every cell, the longest inner loop of the lanes; a walk whose body is
// costly steps through the same entries in one loop instead (hash_walk_step):
//
//     hash_walk w = hash_walk_begin(x);
//     uvec4 entry;
//     bool here;
//     while (hash_walk_step(w, entry, here))
//         if (here)
//             ... point entry.w at uintBitsToFloat(entry.xyz) ...

#ifndef HASH_COMMON_GLSL
#define HASH_COMMON_GLSL

#ifndef HASH_SET
#define HASH_SET 0
#endif

#include "shared/layout.h"

// HASH_FUSED: the whole build in one workgroup (contact_faces_fused.comp,
// contact_edges_fused.comp), whose passes, and the queries after them, read what the passes before them
// wrote in this dispatch: through coherent storage buffers, after memoryBarrierBuffer() and
// barrier(), the parameters too (a uniform buffer need not see them).
#ifdef HASH_FUSED
#define HASH_COHERENT coherent
#define HASH_PARAMS hash_params
#define HASH_ENTRIES_ACCESS coherent
#else
#define HASH_COHERENT
#define HASH_PARAMS hash_params_u
#define HASH_ENTRIES_ACCESS writeonly
#endif

layout(std430, set = HASH_SET, binding = CVK_HASH_BINDING_PARAMS) HASH_COHERENT buffer HashParams {
    cvk_hash_params hash_params;
    uint hash_commands[]; // a build decided on the device: its passes' indirect commands
};
layout(std140, set = HASH_SET, binding = CVK_HASH_BINDING_PARAMS_READ) uniform HashParamsRead {
    cvk_hash_params hash_params_u;
};
layout(set = HASH_SET, binding = CVK_HASH_BINDING_POINTS, rgba32f) uniform readonly imageBuffer hash_points;
layout(std430, set = HASH_SET, binding = CVK_HASH_BINDING_KEYS) HASH_COHERENT buffer HashKeys {
    uint hash_keys[];
};
layout(std430, set = HASH_SET, binding = CVK_HASH_BINDING_STARTS) HASH_COHERENT buffer HashStarts {
    uint hash_starts[];
};
layout(std430, set = HASH_SET, binding = CVK_HASH_BINDING_SCRATCH) HASH_COHERENT buffer HashScratch {
    uint hash_scratch[];
};
// The starts and the entries as queries read them: storage texel loads are inline vectorised
// gathers on lavapipe, where a storage-buffer load in a divergent loop is a loop over the lanes.
layout(set = HASH_SET, binding = CVK_HASH_BINDING_STARTS_READ, r32ui) uniform readonly uimageBuffer hash_starts_read;
layout(std430, set = HASH_SET, binding = CVK_HASH_BINDING_ENTRIES) HASH_ENTRIES_ACCESS buffer HashEntries {
    uvec4 hash_entries[]; // per entry: its point's xyz (float bits), its index
};
layout(set = HASH_SET, binding = CVK_HASH_BINDING_ENTRIES_READ, rgba32ui) uniform readonly uimageBuffer hash_entries_read;
layout(set = HASH_SET, binding = CVK_HASH_BINDING_SALTS, r32ui) uniform readonly uimageBuffer hash_salts;
layout(set = HASH_SET, binding = CVK_HASH_BINDING_SCRATCH_READ, r32ui) uniform readonly uimageBuffer hash_scratch_read;

// The cell of a point: floor(p / cell_size), as a product with the reciprocal so that host and
// device round alike (a multiplication is correctly rounded; a division need not be), clamped
// so the conversion to int is defined. lib/contact/hash.c computes the same.
ivec3 hash_cell(vec3 p)
{
    vec3 c = floor(p * HASH_PARAMS.inv_cell);
    return ivec3(clamp(c, vec3(-CVK_HASH_CELL_LIMIT), vec3(CVK_HASH_CELL_LIMIT)));
}

// The slot of a cell: Teschner et al.'s primes, XORed, then a multiply-xorshift finaliser so the
// low bits the mask keeps depend on every bit of the cell. Integer math only: the host's
// cvk_hash_slot is the same function.
// A salt (the point's, hash_salt) is mixed in before the finaliser, so points of different
// salts in one cell mostly take different slots; salt 0 leaves the slot as it was.
uint hash_slot(ivec3 cell, uint salt)
{
    uvec3 u = uvec3(cell);
    uint h = (u.x * 73856093u) ^ (u.y * 19349663u) ^ (u.z * 83492791u) ^ (salt * 0x9e3779b1u);
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    return h & (HASH_PARAMS.table_size - 1u);
}

uint hash_slot(ivec3 cell)
{
    return hash_slot(cell, 0u);
}

// Point p's salt (lib/contact/hash.h: 0 for every point of a hash made without salts, whose
// salts are one texel of zeros, so a point past the texels has salt 0).
uint hash_salt(uint p)
{
    return p < uint(imageSize(hash_salts)) ? imageLoad(hash_salts, int(p)).x : 0u;
}

const uint HASH_HOME = 13u; // the cell n of the block at offset (0, 0, 0)

// Cell n (0..26) of the 3x3x3 block around `home`.
ivec3 hash_neighbour_cell(ivec3 home, uint n)
{
    return home + ivec3(int(n % 3u) - 1, int((n / 3u) % 3u) - 1, int(n / 9u) - 1);
}

// Word i of a uint buffer as a pass after the one that wrote it reads it: through its texel
// view, a vectorised gather on lavapipe, where a storage load in a loop is a loop over the
// lanes; the fused build reads what it wrote, through the buffer.
#ifdef HASH_FUSED
#define HASH_WORD(buffer, view, i) (buffer[i])
#else
#define HASH_WORD(buffer, view, i) (imageLoad(view, int(i)).x)
#endif

// Slot s's start as the build's passes after the scan and the queries read it.
uint hash_start(uint s)
{
    return HASH_WORD(hash_starts, hash_starts_read, s);
}

// The entries [x, y) of the slot of `cell`: points of that cell and of any cell sharing its slot.
uvec2 hash_range(ivec3 cell, uint salt)
{
    uint s = hash_slot(cell, salt);
    return uvec2(hash_start(s), hash_start(s + 1u));
}

uvec2 hash_range(ivec3 cell)
{
    return hash_range(cell, 0u);
}

vec3 hash_point(uint q)
{
#ifdef HASH_POINT_OF
    return HASH_POINT_OF(q); // the points as the including shader wrote them in this dispatch
#else
    return imageLoad(hash_points, int(q)).xyz;
#endif
}

// Entry e's point index (w) and its point (xyz, as float bits) in one fetch.
uvec4 hash_entry_point(uint e)
{
#ifdef HASH_FUSED
    return hash_entries[e];
#else
    return imageLoad(hash_entries_read, int(e));
#endif
}

// Whether some point of `cell` can lie within sqrt(reach2) of x: its box, widened by a
// thousandth of a cell and a millionth of its coordinates against the rounding of hash_cell
// and of the box's bounds, comes that near (a clamped cell's points lie anywhere; reach2 < 0:
// every cell).
bool hash_cell_near(ivec3 cell, vec3 x, float reach2)
{
    if (reach2 < 0.0 || any(greaterThanEqual(abs(cell), ivec3(CVK_HASH_CELL_LIMIT))))
        return true;
    float size = 1.0 / hash_params_u.inv_cell;
    vec3 low = vec3(cell) * size, high = low + size;
    vec3 far = max(abs(low), abs(high));
    float slack = 1.0e-3 * size + 1.0e-6 * max(far.x, max(far.y, far.z));
    vec3 out_of = max(max(low - x, x - high) - slack, vec3(0.0));
    return dot(out_of, out_of) <= reach2;
}

// The walk over the 27 cells around a point, one entry per step.
// With a salt, the slots that salt's points take (others of other salts may share them: the
// caller tells them apart).
struct hash_walk {
    ivec3 home, cell;
    uvec2 range; // the entries of the visited cell's slot not yet stepped over
    uint n;      // the visited cell, 0..26
    uint salt;
};

hash_walk hash_walk_begin(vec3 x, uint salt, float reach2)
{
    hash_walk w;
    w.home = hash_cell(x);
    w.n = 0u;
    w.salt = salt;
    w.cell = hash_neighbour_cell(w.home, 0u);
    w.range = hash_cell_near(w.cell, x, reach2) ? hash_range(w.cell, salt) : uvec2(0u);
    return w;
}

hash_walk hash_walk_begin(vec3 x, uint salt)
{
    return hash_walk_begin(x, salt, -1.0);
}

// The walk over half the block: the home cell (n = 13) and the 13 after it, whose offsets are
// the negations of those before it. A query that every point makes, counting a pair of points
// in cells a and b from a only when b is after a, and a pair in one cell from one of the two,
// meets every pair once.
hash_walk hash_walk_begin_half(vec3 x, uint salt)
{
    hash_walk w;
    w.home = hash_cell(x);
    w.n = HASH_HOME;
    w.salt = salt;
    w.cell = w.home;
    w.range = hash_range(w.cell, salt);
    return w;
}

hash_walk hash_walk_begin(vec3 x)
{
    return hash_walk_begin(x, 0u);
}

// The walk moved on to its next cell (w.n 27: done), its slot's entries not yet stepped over
// (none where no point of the cell can be within sqrt(reach2) of x, reach2 >= 0).
void hash_walk_next_cell(inout hash_walk w, vec3 x, float reach2)
{
    if (++w.n < 27u) {
        w.cell = hash_neighbour_cell(w.home, w.n);
        w.range = hash_cell_near(w.cell, x, reach2) ? hash_range(w.cell, w.salt) : uvec2(0u);
    }
}

// The next entry of the visited cell's slot, and whether it lies in that cell (here), not in
// another cell sharing the slot.
uvec4 hash_walk_entry(inout hash_walk w, out bool here)
{
    uvec4 entry = hash_entry_point(w.range.x++);
    here = hash_cell(uintBitsToFloat(entry.xyz)) == w.cell;
    return entry;
}

// One step: false once the 27 cells are done; else `entry` (its point's xyz as float bits, its
// index in w) with `here` true where the entry lies in the visited cell, or `here` false at a
// step that moved on to the next cell or met an entry of another cell sharing the slot. With
// reach2 >= 0 a cell none of whose points can be within sqrt(reach2) of x is stepped over
// without its entries (hash_cell_near): a query of a ball as wide as a cell visits about 21 of
// the 27.
bool hash_walk_step(inout hash_walk w, vec3 x, float reach2, out uvec4 entry, out bool here)
{
    entry = uvec4(0u);
    here = false;
    if (w.range.x == w.range.y) {
        hash_walk_next_cell(w, x, reach2);
        return w.n < 27u;
    }
    entry = hash_walk_entry(w, here);
    return true;
}

bool hash_walk_step(inout hash_walk w, out uvec4 entry, out bool here)
{
    return hash_walk_step(w, vec3(0.0), -1.0, entry, here);
}

// Whether point q lies in `cell` (and not in another cell that shares its slot).
bool hash_in_cell(uint q, ivec3 cell)
{
    return hash_cell(hash_point(q)) == cell;
}

#ifdef HASH_BUILD
layout(local_size_x_id = 0) in;

// The build's push data (a shader that builds and queries declares the fields of both,
// CVK_CONTACT_HASH_PUSH_FIELDS, and defines HASH_PUSH_DECLARED).
#ifndef HASH_PUSH_DECLARED
CVK_DECLARE_PUSH(CVK_HASH_PUSH_FIELDS)
#endif

// Invocations stride over the dispatch, so a few workgroups can cover many items.
uint hash_stride()
{
    return gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

// The build's passes, in their order (lib/contact/hash.c): each a dispatch of its own
// (hash_*.comp), or all in one workgroup (HASH_FUSED).

// The hash build, clear: the parameters from the push data; with no points, every start zeroed
// so queries find nothing. (The counts are 0 already: zeroed at creation, and every build's
// scatter counts them back down.) A dispatch rather than buffer fills, so the whole build
// orders itself with compute barriers alone (a fill would need the op before it, possibly
// another module's, to wait for transfers too).
void hash_clear_pass()
{
    if (gl_GlobalInvocationID.x == 0u) {
        if (pc.cell_size > 0.0) { // 0: written on the device before the build (hash.h)
            hash_params.cell_size = pc.cell_size;
            hash_params.inv_cell = pc.inv_cell;
        }
        hash_params.table_size = pc.slots;
        hash_params.count = pc.points;
        if (pc.points == 0u)
            hash_starts[pc.slots] = 0u;
    }
    if (pc.points == 0u)
        for (uint s = gl_GlobalInvocationID.x; s < pc.slots; s += hash_stride())
            hash_starts[s] = 0u;
}

// The hash build, count: each point's slot (its cell's, with its salt) into keys, and one
// more in its slot's count (scratch[slot], zeroed by the fill before this pass).
void hash_count_pass()
{
    for (uint p = gl_GlobalInvocationID.x; p < pc.points; p += hash_stride()) {
        uint s = hash_slot(hash_cell(hash_point(p)), hash_salt(p));
        hash_keys[p] = s;
        atomicAdd(hash_scratch[s], 1u);
    }
}

// Word i of scratch (counts, chunk sums) as the scan reads it: a storage load in its loops was a
// loop over the lanes.
uint hash_scratch_at(uint i)
{
    return HASH_WORD(hash_scratch, hash_scratch_read, i);
}

// The hash build, scan 1 of 3: the sum of the counts of each chunk of `chunk` slots, one
// invocation per chunk, into scratch[slots + chunk index]. A serial loop per invocation and no
// shared memory: on lavapipe a workgroup barrier costs more than the loop.
void hash_chunk_sums_pass()
{
    for (uint c = gl_GlobalInvocationID.x; c < pc.chunks; c += hash_stride()) {
        uint first = c * pc.chunk;
        uint sum = 0u;
        for (uint k = 0u; k < pc.chunk; k++)
            sum += hash_scratch_at(first + k);
        hash_scratch[pc.slots + c] = sum;
    }
}

// The hash build, scan 2 of 3: one invocation turns the chunk sums into their exclusive prefix
// sums (in place) and writes the total, the end of the last slot, to starts[slots]. Chunks
// are about sqrt(slots), so this serial loop is as short as each chunk's.
void hash_scan_chunks_pass()
{
    if (gl_GlobalInvocationID.x != 0u)
        return;
    uint running = 0u;
    for (uint c = 0u; c < pc.chunks; c++) {
        uint sum = hash_scratch[pc.slots + c];
        hash_scratch[pc.slots + c] = running;
        running += sum;
    }
    hash_starts[pc.slots] = running;
}

// The hash build, scan 3 of 3: within each chunk, the exclusive prefix sum of the counts from
// the chunk's offset gives each slot's start. The counts stay: the scatter counts them down.
void hash_scan_pass()
{
    for (uint c = gl_GlobalInvocationID.x; c < pc.chunks; c += hash_stride()) {
        uint running = hash_scratch_at(pc.slots + c);
        uint first = c * pc.chunk;
        for (uint k = 0u; k < pc.chunk; k++) {
            uint n = hash_scratch_at(first + k);
            hash_starts[first + k] = running;
            running += n;
        }
    }
}

// The hash build, scatter: each point, with its position, takes a place of its slot's range in
// the entries, counting the slot's count down (atomic): the order within a slot depends on
// timing, and no reader depends on it (lib/contact/hash.h). Every count ends at 0, ready for the
// next build without a clear (lib/contact/hash.c zeroes them once, at creation).
void hash_scatter_pass()
{
    for (uint p = gl_GlobalInvocationID.x; p < pc.points; p += hash_stride()) {
        uint s = hash_keys[p];
        uint e = hash_start(s) + atomicAdd(hash_scratch[s], 0xffffffffu) - 1u;
        hash_entries[e] = uvec4(floatBitsToUint(hash_point(p)), p);
    }
}

#ifdef HASH_FUSED
// The whole build in one workgroup, its passes in order with a workgroup barrier after each
// (the last too, so the queries after it see the hash), nothing but that barrier while the
// parameters close the build. Call from uniform control flow, after a barrier that made the
// parameters visible.
void hash_build_fused()
{
    if (hash_params.build != 0u) { // the same for every invocation
        hash_clear_pass();
        if (pc.points != 0u) {
            memoryBarrierBuffer();
            barrier();
            hash_count_pass();
            memoryBarrierBuffer();
            barrier();
            hash_chunk_sums_pass();
            memoryBarrierBuffer();
            barrier();
            hash_scan_chunks_pass();
            memoryBarrierBuffer();
            barrier();
            hash_scan_pass();
            memoryBarrierBuffer();
            barrier();
            hash_scatter_pass();
        }
    }
    memoryBarrierBuffer();
    barrier();
}
#endif
#endif

#endif
