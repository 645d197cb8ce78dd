/* libFuzzer harness for the mesh reader (OBJ and PLY through Assimp, then clothvk's welding,
   manifold and degeneracy checks, springs and masses): the input's first byte picks the format,
   the rest is the file, written to a temporary file because Assimp picks its importer by the
   file's extension. Besides the sanitizers, each input checks the reader's contract, and a
   breach aborts with what it was:
   - a refusal is one line that starts with the key path and names the file ("cloths.0.mesh:
     cannot read PATH: ..."), and error.result is the result returned;
   - an accepted mesh has triangles, and springs between its own vertices, finite coordinates
     and positive masses.
   Built and run by scripts/fuzz.sh. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "topology/topology.h"

static void require(bool ok, const char* what, const char* detail)
{
    if (ok)
        return;
    fprintf(stderr, "fuzz_mesh: %s: %s\n", what, detail);
    abort();
}

static void check_refusal(cvk_result r, const cvk_error* err, const char* path)
{
    const char* end = memchr(err->message, '\0', sizeof err->message);
    require(end != NULL, "the message", "not ended within its buffer");
    require(err->result == r, "error.result", err->message);
    require(!memchr(err->message, '\n', (size_t)(end - err->message)), "the message is not one line",
            err->message);
    require(strncmp(err->message, "cloths.0.mesh: ", 15) == 0,
            "the message does not start with the key path", err->message);
    require(strstr(err->message, path) != NULL, "the message does not name the file", err->message);
}

static void check_mesh(const cvk_topology* t)
{
    require(t->triangle_count > 0, "an accepted mesh", "has no triangle");
    for (uint32_t i = 0; i < 3 * t->triangle_count; i++)
        require(t->triangles[i] < t->vertex_count, "an accepted mesh", "a corner past its vertices");
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        require(isfinite(t->position[3 * v]) && isfinite(t->position[3 * v + 1]) &&
                    isfinite(t->position[3 * v + 2]),
                "an accepted mesh", "a coordinate not finite");
        require(t->mass[v] > 0.0f && isfinite(t->mass[v]), "an accepted mesh",
                "a mass not finite and positive");
    }
    for (uint32_t s = 0; s < t->spring_count; s++)
        require(t->springs[s].a != t->springs[s].b && t->springs[s].a < t->vertex_count &&
                    t->springs[s].b < t->vertex_count,
                "an accepted mesh", "a spring not between two of its vertices");
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    char path[64];
    snprintf(path, sizeof path, "/tmp/clothvk-fuzz-%ld.%s", (long)getpid(),
             data[0] & 1 ? "ply" : "obj");
    FILE* f = fopen(path, "wb");
    if (!f)
        return 0;
    fwrite(data + 1, 1, size - 1, f);
    fclose(f);
    cvk_cloth_desc cloth = cvk_default_cloth_desc();
    cloth.mesh = path;
    cloth.stiffness.shear = 1e3f;
    cloth.stiffness.bend = 1e2f;
    cvk_topology topology;
    cvk_error err;
    cvk_result r = cvk_topology_create(&cloth, 0, &topology, &err);
    if (r == CVK_SUCCESS) {
        check_mesh(&topology);
        cvk_topology_destroy(&topology);
    } else {
        check_refusal(r, &err, path);
    }
    unlink(path);
    return 0;
}
