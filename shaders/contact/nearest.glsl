// The nearest-first lists of detection (contact_detect.comp, contact_edges.comp): the including
// shader declares `const uint K`, `const bool DEDUP` and the module-scope arrays `uint kept[K]`
// and `float dist[K]`, then INSERT keeps the K nearest items, equal distances by item, so a
// list depends neither on thread timing nor on the order of the walk.
#ifndef CONTACT_NEAREST_GLSL
#define CONTACT_NEAREST_GLSL

const float INFINITY = 3.0e38; // beyond any distance kept

// Whether the kept (dist_k, kept_k) comes after (d, item).
bool after(float dist_k, uint kept_k, float d, uint item)
{
    return dist_k > d || (dist_k == d && kept_k > item);
}

// The lists emptied.
void clear_nearest()
{
    for (uint k = 0u; k < K; k++) {
        kept[k] = CVK_NO_CONTACT;
        dist[k] = INFINITY;
    }
}

// (d, item) into the nearest K; with DEDUP not if it is there already (a corner or an edge
// reached through several triangles). Every index a constant once the loop unrolls: a variable
// index into a private array is a per-lane memory loop on lavapipe; a macro, since lavapipe
// copies a function's inout arrays at every call.
#define INSERT(D, ITEM)                                                                   \
    {                                                                                     \
        float new_d = (D);                                                                \
        uint new_item = (ITEM);                                                           \
        bool present = false;                                                             \
        for (uint s = 0u; DEDUP && s < K; s++)                                            \
            present = present || kept[s] == new_item;                                     \
        for (uint s = K - 1u; s > 0u && !present; s--) {                                  \
            bool shift = after(dist[s - 1u], kept[s - 1u], new_d, new_item);              \
            bool here = !shift && after(dist[s], kept[s], new_d, new_item);               \
            kept[s] = shift ? kept[s - 1u] : (here ? new_item : kept[s]);                 \
            dist[s] = shift ? dist[s - 1u] : (here ? new_d : dist[s]);                    \
        }                                                                                 \
        bool front = !present && after(dist[0], kept[0], new_d, new_item);                \
        kept[0] = front ? new_item : kept[0];                                             \
        dist[0] = front ? new_d : dist[0];                                                \
    }

// Within reach of the walk's centre c: the walk's test and the once-only test, one expression
// (precise: both give the same answer for the same point).
bool within_reach(vec3 c, vec3 x, float reach2)
{
    precise vec3 d = x - c;
    precise float d2 = dot(d, d);
    return d2 < reach2;
}

#endif
