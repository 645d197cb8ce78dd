/* What the bench and the tests reach beyond clothvk.h. clothvk-bench measures the library from
   the inside (its solves against a host reference, its spatial hash pass by pass): it links the
   internal archive (clothvk_internal_dep) and reaches it through this header alone. An
   application needs only clothvk.h. Each include says why the bench needs it. */
#ifndef CVK_SIM_INTERNAL_H
#define CVK_SIM_INTERNAL_H

#include "clothvk.h"

/* The context's Vulkan objects (device, properties, timestamp bits): clothvk-bench collide
   records its own command buffers and timestamp queries on them. */
#include "core/context.h"
/* cvk_fail and cvk_fail_vk: a bench experiment's failures in the library's error form. */
#include "core/error.h"
/* Buffers, descriptor sets, command buffers and the submitter: collide's points, results and
   submissions. */
#include "core/gpu.h"
/* Pipelines by id and label, their specialisation inputs: collide's query pipeline. */
#include "core/pipelines.h"
/* cvk_step_params_of: what a step reads of its scene, the host reference solvers' input. */
#include "scene/scene.h"
/* cvk_build: a scene built on the host in the device's particle order, with its springs by
   kind; the host reference solvers and the explicit experiment's stiffest mode work on it. */
#include "topology/build.h"
/* Residuals, solve errors and distances measured on the host, as the simulation's stats. */
#include "topology/metrics.h"
/* Plans of passes and dispatches with timestamp queries: collide times each operation. */
#include "plan/plan.h"
/* The spatial hash: collide times its build and a neighbour query over it. */
#include "contact/hash.h"
/* The double-precision host solvers: the prediction and the converged solution x* (Newton)
   the bench measures the device's solves against. */
#include "solvers/reference.h"
/* The structures shared with the shaders: the neighbour query's push constants. */
#include "shared/layout.h"

#endif
