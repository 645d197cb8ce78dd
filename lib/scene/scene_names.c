/* The names of the scene format's enumerations, as scene files and messages write them
   (cvk_read_enum lists a type's names by asking for 0, 1, 2, ... until NULL). */
#include "clothvk.h"

#include <stddef.h>

const char* cvk_collider_type_name(cvk_collider_type type)
{
    switch (type) {
    case CVK_COLLIDER_PLANE: return "plane";
    case CVK_COLLIDER_SPHERE: return "sphere";
    case CVK_COLLIDER_BOX: return "box";
    case CVK_COLLIDER_CAPSULE: return "capsule";
    case CVK_COLLIDER_FUNNEL: return "funnel";
    case CVK_COLLIDER_MESH: return "mesh";
    case CVK_COLLIDER_TYPE_COUNT: break;
    }
    return NULL;
}

const char* cvk_linear_solver_name(cvk_linear_solver linear)
{
    switch (linear) {
    case CVK_LINEAR_RBGS: return "rbgs";
    case CVK_LINEAR_JACOBI: return "jacobi";
    case CVK_LINEAR_CHEBYSHEV: return "chebyshev";
    case CVK_LINEAR_GS_CPU: return "gs-cpu";
    case CVK_LINEAR_CG: return "cg";
    }
    return NULL;
}

const char* cvk_method_name(cvk_method method)
{
    switch (method) {
    case CVK_METHOD_PD: return "pd";
    case CVK_METHOD_IMPLICIT: return "implicit";
    case CVK_METHOD_EXPLICIT: return "explicit";
    }
    return NULL;
}

const char* cvk_integrator_name(cvk_integrator integrator)
{
    switch (integrator) {
    case CVK_INTEGRATOR_NONE: return "none";
    case CVK_INTEGRATOR_EULER: return "euler";
    case CVK_INTEGRATOR_RK2: return "rk2";
    case CVK_INTEGRATOR_AB4: return "adams-bashforth";
    case CVK_INTEGRATOR_VERLET: return "verlet";
    }
    return NULL;
}

const char* cvk_fuse_name(cvk_fuse fuse)
{
    switch (fuse) {
    case CVK_FUSE_AUTO: return "auto";
    case CVK_FUSE_ON: return "on";
    case CVK_FUSE_OFF: return "off";
    }
    return NULL;
}

const char* cvk_damping_model_name(cvk_damping_model model)
{
    switch (model) {
    case CVK_DAMPING_NONE: return "none";
    case CVK_DAMPING_SPRING: return "spring";
    case CVK_DAMPING_VISCOSITY: return "viscosity";
    }
    return NULL;
}
