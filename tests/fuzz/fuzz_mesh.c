/* libFuzzer harness for the mesh reader (OBJ and PLY through Assimp, then clothvk's welding,
   manifold and degeneracy checks, springs and masses): the input's first byte picks the format,
   the rest is the file, written to a temporary file because Assimp picks its importer by the
   file's extension. Built and run by scripts/fuzz.sh. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "topology/topology.h"

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
    if (cvk_topology_create(&cloth, 0, &topology, &err) == CVK_SUCCESS)
        cvk_topology_destroy(&topology);
    unlink(path);
    return 0;
}
