/* The solver families (plan/family.h is the interface each implements): the table of them,
   and the one that solves a solver description. */
#ifndef CVK_SOLVER_H
#define CVK_SOLVER_H

#include "plan/family.h"


/* Every family, and the one that solves `solver` (NULL: none). */
extern const cvk_family_api cvk_family_pd;
extern const cvk_family_api cvk_family_implicit;
extern const cvk_family_api cvk_family_explicit;
const cvk_family_api* cvk_family_for(const cvk_solver_desc* solver);

#endif
