/* The table of solver families (solvers/solver.h). */
#include "solvers/solver.h"

/* Every family; the first that accepts a solver description solves it. */
static const cvk_family_api* const families[] = {&cvk_family_pd, &cvk_family_implicit,
                                                  &cvk_family_explicit};

const cvk_family_api* cvk_family_for(const cvk_solver_desc* solver)
{
    for (size_t i = 0; i < sizeof families / sizeof families[0]; i++)
        if (families[i]->accepts(solver))
            return families[i];
    return NULL;
}
