/* Exact snapshots: a header that says what the bytes are and which scene they belong to,
   then the solver family's raw state (solver.h), then with self-contact the contact state
   (collide.h: frame state, positions at the last search, candidates), then with tearing the
   spring flags (tear.h: uint32 per spring, 1 or 0 once torn). Loading refuses, with one sentence and
   changing nothing, anything that would not resume this simulation exactly.

   Header, 72 bytes, native byte order (little-endian on every machine clothvk runs on):
     0  char[8]  "CVKSNAP\0"
     8  uint32   format version (CVK_SNAPSHOT_VERSION)
     12 uint32   particle count
     16 uint64   frames simulated
     24 uint64   build hash: FNV-1a over particle counts, initial positions, masses and
                 springs in internal order (another scene, or another build order, differs)
     32 uint64   bytes of state after the header (family, then contact, then tearing)
     40 char[12] solver family ("pd")
     52 char[12] linear solver when taken ("rbgs", ...), for messages
     64 uint32   CRC-32 (zlib's crc32) over every other byte: the header without this field,
                 then the state; a flipped bit anywhere is refused as damage
     68 uint32   0 (the state starts 8-byte aligned) */
#include <stdio.h>
#include <string.h>
#include <zlib.h>

#include "core/error.h"
#include "sim/sim.h"
#include "solvers/solver.h"

/* 2: the projective-dynamics rest memory; 3: the contact work lists; 4: the CRC-32; 5: the
   contact frame state's count of particles held at their bounds; 6: its flag of a detection
   cut short; 7: its count of crowded particles */
#define CVK_SNAPSHOT_VERSION 7u
#define HEADER_SIZE 72u
#define CRC_OFFSET 64u
static const char magic[8] = "CVKSNAP";

typedef struct header {
    uint32_t version, particles;
    uint64_t frames, hash, state_size;
    char family[12], solver[12];
    uint32_t crc;
} header;

/* zlib's crc32 over a buffer of any size (its length argument is 32-bit). */
static uLong crc_more(uLong crc, const unsigned char* p, uint64_t size)
{
    while (size > 0) {
        uInt chunk = size > (1u << 30) ? (1u << 30) : (uInt)size;
        crc = crc32(crc, p, chunk);
        p += chunk;
        size -= chunk;
    }
    return crc;
}

/* The checksum of a whole snapshot: every byte but the CRC field's own. */
static uint32_t snapshot_crc(const unsigned char* data, uint64_t size)
{
    uLong crc = crc_more(crc32(0L, Z_NULL, 0), data, CRC_OFFSET);
    return (uint32_t)crc_more(crc, data + CRC_OFFSET + 4, size - CRC_OFFSET - 4);
}

static uint64_t fnv1a(uint64_t h, const void* data, size_t size)
{
    const unsigned char* p = data;
    for (size_t i = 0; i < size; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

static uint64_t build_hash(const cvk_build* b)
{
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv1a(h, &b->particle_count, sizeof b->particle_count);
    h = fnv1a(h, &b->free_count, sizeof b->free_count);
    h = fnv1a(h, b->position, 3 * (size_t)b->particle_count * sizeof(float));
    h = fnv1a(h, b->mass, (size_t)b->particle_count * sizeof(float));
    for (uint32_t i = 0; i < b->spring_count; i++) { /* field by field: no padding hashed */
        const cvk_spring* sp = &b->springs[i];
        h = fnv1a(h, &sp->a, sizeof sp->a);
        h = fnv1a(h, &sp->b, sizeof sp->b);
        h = fnv1a(h, &sp->rest, sizeof sp->rest);
        h = fnv1a(h, &sp->k, sizeof sp->k);
        h = fnv1a(h, &sp->type, sizeof sp->type);
    }
    return h;
}

uint64_t cvk_sim_snapshot_size(const cvk_sim* s)
{
    return s ? HEADER_SIZE + s->family->snapshot_size(s, s->family_state) +
                   cvk_collide_snapshot_size(s) + cvk_tear_snapshot_size(s)
             : 0;
}

static void write_header(unsigned char* out, const header* h)
{
    memset(out, 0, HEADER_SIZE);
    memcpy(out, magic, sizeof magic);
    memcpy(out + 8, &h->version, 4);
    memcpy(out + 12, &h->particles, 4);
    memcpy(out + 16, &h->frames, 8);
    memcpy(out + 24, &h->hash, 8);
    memcpy(out + 32, &h->state_size, 8);
    memcpy(out + 40, h->family, sizeof h->family);
    memcpy(out + 52, h->solver, sizeof h->solver);
}

static void read_header(const unsigned char* in, header* h)
{
    memcpy(&h->version, in + 8, 4);
    memcpy(&h->particles, in + 12, 4);
    memcpy(&h->frames, in + 16, 8);
    memcpy(&h->hash, in + 24, 8);
    memcpy(&h->state_size, in + 32, 8);
    memcpy(h->family, in + 40, sizeof h->family);
    memcpy(h->solver, in + 52, sizeof h->solver);
    memcpy(&h->crc, in + CRC_OFFSET, 4);
    h->family[sizeof h->family - 1] = h->solver[sizeof h->solver - 1] = '\0';
}

cvk_result cvk_sim_save_snapshot(cvk_sim* s, void* data, uint64_t size, cvk_error* error)
{
    if (!s || !data)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_save_snapshot needs a simulation and a buffer");
    uint64_t need = cvk_sim_snapshot_size(s);
    if (size != need)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_save_snapshot: the buffer holds %llu bytes; the snapshot is %llu "
                        "(cvk_sim_snapshot_size)",
                        (unsigned long long)size, (unsigned long long)need);
    header h = {.version = CVK_SNAPSHOT_VERSION,
                .particles = s->build.particle_count,
                .frames = s->frames,
                .hash = build_hash(&s->build),
                .state_size = need - HEADER_SIZE};
    snprintf(h.family, sizeof h.family, "%s", s->family->name);
    snprintf(h.solver, sizeof h.solver, "%s", cvk_linear_solver_name(s->solver.linear));
    write_header(data, &h);
    unsigned char* state = (unsigned char*)data + HEADER_SIZE;
    uint64_t family = s->family->snapshot_size(s, s->family_state);
    cvk_result r = s->family->save_snapshot(s, s->family_state, state, error);
    if (r == CVK_SUCCESS)
        r = cvk_collide_save_snapshot(s, state + family, error);
    if (r == CVK_SUCCESS)
        r = cvk_tear_save_snapshot(s, state + family + cvk_collide_snapshot_size(s), error);
    if (r == CVK_SUCCESS) {
        uint32_t crc = snapshot_crc(data, size);
        memcpy((unsigned char*)data + CRC_OFFSET, &crc, 4);
    }
    return r;
}

/* Everything the header can say against this simulation, in the order a user can act on. */
static cvk_result check_header(const cvk_sim* s, const unsigned char* in, uint64_t size,
                               header* h, cvk_error* error)
{
    const char* call = "cvk_sim_load_snapshot";
    if (size < HEADER_SIZE || memcmp(in, magic, sizeof magic) != 0)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the data is not a clothvk snapshot (%llu bytes without its header)",
                        call, (unsigned long long)size);
    read_header(in, h);
    if (h->version != CVK_SNAPSHOT_VERSION)
        return cvk_fail(error, CVK_ERROR_UNSUPPORTED,
                        "%s: the snapshot has format version %u; this library reads version %u",
                        call, h->version, CVK_SNAPSHOT_VERSION);
    if (size - HEADER_SIZE != h->state_size)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the snapshot is %llu bytes; its header says %llu (truncated or "
                        "padded)", call, (unsigned long long)size,
                        (unsigned long long)(HEADER_SIZE + h->state_size));
    uint32_t crc = snapshot_crc(in, size);
    if (crc != h->crc)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the snapshot is damaged: its CRC-32 is %08x, its header says %08x",
                        call, crc, h->crc);
    if (strcmp(h->family, s->family->name) != 0)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the snapshot holds the state of solver family \"%s\"; this "
                        "simulation's is \"%s\"", call, h->family, s->family->name);
    uint64_t hash = build_hash(&s->build);
    if (h->particles != s->build.particle_count || h->hash != hash)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "%s: the snapshot was taken of another scene (%u particles, build hash "
                        "%016llx; this simulation: %u particles, %016llx)",
                        call, h->particles, (unsigned long long)h->hash,
                        s->build.particle_count, (unsigned long long)hash);
    return CVK_SUCCESS;
}

cvk_result cvk_sim_load_snapshot(cvk_sim* s, const void* data, uint64_t size, cvk_error* error)
{
    if (!s || !data)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_load_snapshot needs a simulation and the snapshot's bytes");
    header h;
    cvk_result r = check_header(s, data, size, &h, error);
    uint64_t tear = cvk_tear_snapshot_size(s);
    uint64_t contact = cvk_collide_snapshot_size(s);
    if (r == CVK_SUCCESS && h.state_size < contact + tear)
        r = cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                     "cvk_sim_load_snapshot: the snapshot holds %llu bytes of state, less than "
                     "this simulation's %s alone (%llu): taken without %s?",
                     (unsigned long long)h.state_size,
                     tear ? "cloth contact state and spring flags" : "cloth contact state",
                     (unsigned long long)(contact + tear),
                     tear ? "self-contact or tearing" : "self-contact");
    const unsigned char* state = (const unsigned char*)data + HEADER_SIZE;
    uint64_t family = r == CVK_SUCCESS ? h.state_size - contact - tear : 0;
    if (r == CVK_SUCCESS)
        r = s->family->load_snapshot(s, s->family_state, state, family, error);
    if (r == CVK_SUCCESS) /* torn springs stay torn: flags and adjacency as they were */
        r = cvk_tear_load_snapshot(s, state + family + contact, error);
    uint64_t step = r == CVK_SUCCESS ? h.frames * s->params.substeps : 0;
    if (r == CVK_SUCCESS && contact > 0) { /* the frame state, the clock included; the poses */
        r = cvk_collide_load_snapshot(s, state + family, error);
        if (r == CVK_SUCCESS)
            r = cvk_collide_write_poses(s, step, error);
    } else if (r == CVK_SUCCESS && (s->collide->collider_count > 0 || s->attach->attachment_count > 0 ||
                                    s->aero->enabled)) { /* the clock of colliders, attachments, gusts */
        r = cvk_collide_set_step(s, step, error);
    }
    if (r == CVK_SUCCESS) {
        s->frames = h.frames;
        cvk_sim_watch_reset(s);
    }
    return r;
}
