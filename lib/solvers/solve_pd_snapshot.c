/* Exact snapshots of the projective-dynamics state. Between substeps the family's state is
   the positions, the last displacement u[0] and the rest memory (solve_pd.h): every other
   buffer (u[1], y, rhs) is written by a substep before it reads it, and pinned entries never
   change. So a snapshot is those arrays exactly as they are held: on the device vec4 floats
   (w included) in internal order, for gs-cpu the host's doubles x, x_prev and rest.
   Converting between the two would not be exact, so a snapshot loads only where the state
   lives on the same side; among the device solvers (rbgs, jacobi, chebyshev) the state is the
   same and loads across.

   Layout (native byte order): uint32 storage (PD_DEVICE or PD_HOST), uint32 0, then
   device: positions[n] vec4, u0[n] vec4, rest[nf] vec4 (nf free particles, at least 1);
   host: x[3n] doubles, x_prev[3n] doubles, rest[3n] doubles. */
#include <string.h>

#include "core/error.h"
#include "solvers/solve_pd.h"
#include "solvers/velocity_state.h"

enum { PD_DEVICE = 1, PD_HOST = 2 };
#define PD_PREFIX 8u

static uint64_t payload_size(uint32_t storage, const cvk_pd* pd, uint64_t n)
{
    return PD_PREFIX + (storage == PD_HOST ? 9u * sizeof(double) * n : 32u * n + pd->rest.size);
}

uint64_t cvk_pd_snapshot_size(const cvk_sim* s, const void* self)
{
    const cvk_pd* pd = self;
    return payload_size(pd->host ? PD_HOST : PD_DEVICE, pd, s->build.particle_count);
}

cvk_result cvk_pd_save_snapshot(cvk_sim* s, void* self, void* data, cvk_error* error)
{
    cvk_pd* pd = self;
    uint64_t n = s->build.particle_count;
    uint32_t prefix[2] = {pd->host ? PD_HOST : PD_DEVICE, 0};
    unsigned char* out = data;
    memcpy(out, prefix, sizeof prefix);
    out += PD_PREFIX;
    if (pd->host) {
        memcpy(out, pd->hx, 3 * n * sizeof(double));
        memcpy(out + 3 * n * sizeof(double), pd->hprev, 3 * n * sizeof(double));
        memcpy(out + 6 * n * sizeof(double), pd->hrest, 3 * n * sizeof(double));
        return CVK_SUCCESS;
    }
    cvk_result r = cvk_vstate_save(s, pd->readback_cmd, out, error); /* positions, then u[0] */
    if (r == CVK_SUCCESS)
        r = cvk_buffer_download(s->device.context, &s->device.submitter, s->device.transfer_cmd, &pd->rest,
                                out + 32u * n, pd->rest.size, error);
    return r;
}

static const char* side_name(uint32_t storage)
{
    return storage == PD_HOST ? "the gs-cpu solver's host state"
                              : "a device solver's state (rbgs, jacobi or chebyshev)";
}

/* Refuses bytes of another layout or size, before anything changes. */
static cvk_result check_payload(const cvk_sim* s, const cvk_pd* pd, const void* data,
                                uint64_t size, cvk_error* error)
{
    uint32_t prefix[2] = {0, 0};
    if (size >= PD_PREFIX)
        memcpy(prefix, data, sizeof prefix);
    if (prefix[0] != PD_DEVICE && prefix[0] != PD_HOST)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_load_snapshot: the projective-dynamics state is malformed "
                        "(unknown storage %u)", prefix[0]);
    uint32_t here = pd->host ? PD_HOST : PD_DEVICE;
    if (prefix[0] != here)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_load_snapshot: the snapshot holds %s; this simulation solves "
                        "with %s: set that kind of solver first (cvk_sim_set_solver)",
                        side_name(prefix[0]), cvk_linear_solver_name(s->solver.linear));
    uint64_t want = payload_size(here, pd, s->build.particle_count);
    if (size != want)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_load_snapshot: the projective-dynamics state is %llu bytes; "
                        "%llu expected", (unsigned long long)size, (unsigned long long)want);
    return CVK_SUCCESS;
}

cvk_result cvk_pd_load_snapshot(cvk_sim* s, void* self, const void* data, uint64_t size,
                                cvk_error* error)
{
    cvk_pd* pd = self;
    cvk_result r = check_payload(s, pd, data, size, error);
    if (r != CVK_SUCCESS)
        return r;
    uint64_t n = s->build.particle_count;
    const unsigned char* in = (const unsigned char*)data + PD_PREFIX;
    if (pd->host) {
        memcpy(pd->hx, in, 3 * n * sizeof(double));
        memcpy(pd->hprev, in + 3 * n * sizeof(double), 3 * n * sizeof(double));
        memcpy(pd->hrest, in + 6 * n * sizeof(double), 3 * n * sizeof(double));
        memcpy(pd->hy, pd->hx, 3 * n * sizeof(double)); /* pinned entries: where they are held */
        return cvk_pd_upload_host_positions(s, pd, error);
    }
    /* The rest memory first (through the staging buffer), then as set_state: u[1] and y start
       equal to u[0]; each substep overwrites them first. */
    memcpy(s->device.staging.mapped, in + 32u * n, pd->rest.size);
    cvk_staging_copy rest = {&pd->rest, 0, 0, pd->rest.size};
    r = cvk_device_copy_from_staging(&s->device, &rest, 1, error);
    if (r != CVK_SUCCESS)
        return r;
    memcpy(s->device.staging.mapped, in, 32u * n);
    return cvk_pd_upload_staged_state(s, pd, error);
}
