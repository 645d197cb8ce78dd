// The partial sums of a projective-dynamics convergence check and one squared residual per
// free particle (shared/layout.h, CVK_PD_PARTIALS), at binding CONVERGE_SUMS of set 0: bound
// in every set of the family (the checking sweeps write the residuals) and in the check's own.
layout(std430, set = 0, binding = CONVERGE_SUMS) buffer Converge {
    float partials[CVK_PD_PARTIALS];
    float residual[];
};
