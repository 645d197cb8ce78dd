// Strain limiting (solver.strain_limit), in place on the iterate the last sweep wrote (dst),
// for the strain pass (pd_strain.comp, one colour a dispatch) and the fused sweeps
// (pd_fused.comp, one colour between two barriers): a particle whose springs are longer than
// `limit` (1 + strain_limit) times their rest lengths moves to shorten them — by the mean of
// the moves that would bring each such spring back to the limit (to its neighbour's current
// place: a particle of another colour, which is not written while this colour is, so the
// result does not depend on the order of invocations), at most `most` m (0: any), then within
// its bound. A particle no spring of which is past the limit keeps its iterate bit for bit.
// Include after pd_common.glsl.

void strain_one(uint p, float limit, float most, vec3 shift)
{
    vec4 cur = LOAD_DST(p);
    vec3 xp = fetch(x_read, p) + cur.xyz;
    vec3 move = vec3(0.0);
    float over = 0.0;
    for (uint q = 0; q < QUADS; q++) {
        uvec4 n = quad_neighbours(q, p);
        vec4 k = quad_k(q, p);
        vec4 rest = imageLoad(adjacency_rest, int(q * pc.stride + p));
        for (uint j = 0; j < 4u; j++) {
            vec3 t = xp - (fetch(x_read, n[j]) + FETCH_DST(n[j]));
            float len2 = dot(t, t), longest = limit * rest[j];
            // Padding slots (k 0, p itself) and springs within the limit take no part.
            bool past = k[j] > 0.0 && len2 > longest * longest;
            float len = sqrt(len2);
            move += past ? t * ((longest - len) / len) : vec3(0.0);
            over += past ? 1.0 : 0.0;
        }
    }
    // w 1: the next outer iteration's first sweep does not over-relax a particle moved
    // here (as after contact, pd_gauss_seidel.comp): it would throw it past the solve.
    move /= max(over, 1.0);
    float len = length(move);
    if (most > 0.0 && len > most)
        move *= most / len;
    if (over > 0.0)
        STORE_DST(p, vec4(bounded(p, cur.xyz + move, shift), 1.0));
}
