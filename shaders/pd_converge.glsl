// The convergence state of a projective-dynamics solve with a tolerance, its partial sums and
// one squared residual per free particle (shared/layout.h, CVK_PD_PARTIALS); bound in every
// set of the family, used by the checking sweeps and shaders/pd_converge.comp only.
layout(std430, set = 0, binding = CVK_PD_BINDING_CONVERGE) buffer Converge {
    cvk_pd_scalars scalars;
    float partials[CVK_PD_PARTIALS];
    float residual[];
};
