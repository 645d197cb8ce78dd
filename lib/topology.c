/* Topologies: what every cloth is made of before build.c sees it. */
#include "topology.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "error.h"

cvk_result cvk_topology_area_mass(cvk_topology* t, double density, double total_mass,
                                  cvk_error* error)
{
    double* area = calloc(t->vertex_count ? t->vertex_count : 1, sizeof(double));
    if (!area)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "out of host memory for %u masses",
                        t->vertex_count);
    double total_area = 0.0;
    for (uint32_t tri = 0; tri < t->triangle_count; tri++) {
        const uint32_t* v = &t->triangles[3 * (size_t)tri];
        const float* p0 = &t->position[3 * (size_t)v[0]];
        const float* p1 = &t->position[3 * (size_t)v[1]];
        const float* p2 = &t->position[3 * (size_t)v[2]];
        double e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = (double)p1[k] - p0[k];
            e2[k] = (double)p2[k] - p0[k];
        }
        double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        double a = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        total_area += a;
        for (int k = 0; k < 3; k++)
            area[v[k]] += a / 3.0;
    }
    for (uint32_t v = 0; v < t->vertex_count; v++) {
        if (total_area <= 0.0)
            t->mass[v] = (float)(total_mass / t->vertex_count);
        else if (density > 0.0)
            t->mass[v] = (float)(density * area[v]);
        else
            t->mass[v] = (float)(total_mass * area[v] / total_area);
    }
    free(area);
    return CVK_SUCCESS;
}
