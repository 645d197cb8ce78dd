/* Contact figures measured on the host from positions: how many particles touch a collider,
   the deepest one inside, how many particle–triangle pairs of the cloths are within the
   thickness, and how many triangle pairs intersect (intersect.h). They check the device's
   contact handling from outside it, so nothing here shares its code: distances come from
   cvk_collide_distance (the host's reference of the collider shapes) and the particle–triangle
   pairs from the host's grid of boxes (intersect.h), measured in double. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "contact/intersect.h"
#include "sim/sim.h"

#define CONTACT_MARGIN 1e-4 /* m: a particle this far outside the thickness still touches */

/* The live triangles in internal particle indices; torn ones keep three equal indices. */
static cvk_result live_triangles(cvk_sim* s, uint32_t** out, cvk_error* error)
{
    const cvk_build* b = &s->build;
    size_t n = 3 * (size_t)b->triangle_count;
    uint32_t* t = malloc((n ? n : 1) * sizeof *t);
    if (!t)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "contact statistics: out of host memory for %u triangles",
                        b->triangle_count);
    cvk_result r = cvk_sim_read_mesh(s, NULL, NULL, t, b->particle_count, b->triangle_count,
                                     error);
    if (r != CVK_SUCCESS) {
        free(t);
        return r;
    }
    for (size_t i = 0; i < n; i++)
        t[i] = b->internal_of[t[i]];
    *out = t;
    return CVK_SUCCESS;
}

cvk_result cvk_sim_count_intersections(cvk_sim* s, uint64_t* out_pairs, cvk_error* error)
{
    if (!s || !out_pairs)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "cvk_sim_count_intersections needs a simulation and an output count");
    *out_pairs = 0;
    const cvk_build* b = &s->build;
    size_t n = b->particle_count;
    float* xyz = malloc((n ? 3 * n : 1) * sizeof *xyz);
    uint32_t* tri = malloc((b->triangle_count ? 3 * (size_t)b->triangle_count : 1) * sizeof *tri);
    cvk_result r = CVK_SUCCESS;
    if (!xyz || !tri)
        r = cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                     "cvk_sim_count_intersections: out of host memory for %u particles",
                     b->particle_count);
    uint32_t* groups = NULL;
    if (r == CVK_SUCCESS)
        r = cvk_sim_read_mesh(s, xyz, NULL, tri, n, b->triangle_count, error);
    if (r == CVK_SUCCESS)
        r = cvk_collide_triangle_instances(b, s->collide->instance_count, &groups, error);
    if (r == CVK_SUCCESS)
        r = cvk_count_intersecting_pairs(xyz, b->particle_count, tri, groups, b->triangle_count,
                                         out_pairs, error);
    free(groups);
    free(xyz);
    free(tri);
    return r;
}

/* ---- the clean start ------------------------------------------------------------------------ */

static uint32_t cloth_of_triangle(const cvk_build* b, uint32_t t)
{
    uint32_t c = 0;
    while (c + 1 < b->cloth_count && t >= b->cloths[c + 1].first_triangle)
        c++;
    return c;
}

static cvk_result fail_intersecting(const cvk_build* b, const cvk_intersecting_pair* p,
                                    cvk_error* error)
{
    uint32_t ca = cloth_of_triangle(b, p->first), cb = cloth_of_triangle(b, p->second);
    uint32_t ta = p->first - b->cloths[ca].first_triangle;
    uint32_t tb = p->second - b->cloths[cb].first_triangle;
    const char* na = b->cloths[ca].name;
    const char* nb = b->cloths[cb].name;
    static const char fix[] = "set collision.allow_intersecting_start to simulate anyway";
    if (ca == cb)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                        "collision: cloth \"%s\" intersects itself at the start (triangles %u "
                        "and %u, near (%.3f, %.3f, %.3f)); %s", na, ta, tb, (double)p->near[0],
                        (double)p->near[1], (double)p->near[2], fix);
    return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                    "collision: cloths \"%s\" and \"%s\" intersect at the start (triangle %u of "
                    "\"%s\" and triangle %u of \"%s\", near (%.3f, %.3f, %.3f)); %s", na, nb, ta,
                    na, tb, nb, (double)p->near[0], (double)p->near[1], (double)p->near[2], fix);
}

cvk_result cvk_sim_check_clean_start(const cvk_sim* s, const cvk_scene_desc* scene,
                                     cvk_error* error)
{
    if (!scene->collision.self || scene->collision.allow_intersecting_start)
        return CVK_SUCCESS;
    const cvk_build* b = &s->build;
    size_t n = 3 * (size_t)b->triangle_count;
    uint32_t* tri = malloc((n ? n : 1) * sizeof *tri);
    if (!tri)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "collision: out of host memory for %u triangles", b->triangle_count);
    for (size_t i = 0; i < n; i++)
        tri[i] = b->internal_of[b->triangles[i]];
    cvk_intersecting_pair pair;
    uint32_t* groups = NULL;
    cvk_result r = cvk_collide_triangle_instances(b, cvk_collide_instance_count(b, scene), &groups,
                                                  error);
    if (r == CVK_SUCCESS)
        r = cvk_first_intersecting_pair(b->position, b->particle_count, tri, groups,
                                        b->triangle_count, &pair, error);
    free(groups);
    free(tri);
    if (r == CVK_SUCCESS && pair.found)
        r = fail_intersecting(b, &pair, error);
    return r;
}

/* ---- a start inside a collider ------------------------------------------------------------ */

/* The cloth of user particle u, and u's index within it. */
static uint32_t cloth_of_particle(const cvk_build* b, uint32_t u, uint32_t* index)
{
    uint32_t c = 0;
    while (c + 1 < b->cloth_count && u >= b->cloths[c + 1].first_user)
        c++;
    *index = u - b->cloths[c].first_user;
    return c;
}

static cvk_result fail_inside(const cvk_sim* s, uint32_t p, uint32_t k, float depth,
                              cvk_error* error)
{
    const cvk_build* b = &s->build;
    const cvk_collide* c = s->collide;
    uint32_t v;
    const cvk_cloth_range* cloth = &b->cloths[cloth_of_particle(b, b->user_of[p], &v)];
    char particle[48], collider[96];
    if (cloth->grid[0])
        snprintf(particle, sizeof particle, "particle [%u, %u]", v % cloth->grid[0],
                 v / cloth->grid[0]);
    else
        snprintf(particle, sizeof particle, "vertex %u", v);
    uint32_t index = k % c->instance_colliders;
    const char* name = c->colliders[k].name;
    if (name)
        snprintf(collider, sizeof collider, "colliders.%u (\"%s\")", index, name);
    else
        snprintf(collider, sizeof collider, "colliders.%u", index);
    const float* x = &b->position[3 * (size_t)p];
    return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT,
                    "collision: cloth \"%s\" starts inside %s: its %s is %.3g m inside, at "
                    "(%.3f, %.3f, %.3f); set collision.allow_intersecting_start to simulate "
                    "anyway", cloth->name, collider, particle, (double)depth, (double)x[0],
                    (double)x[1], (double)x[2]);
}

cvk_result cvk_sim_check_collider_start(const cvk_sim* s, const cvk_scene_desc* scene,
                                        cvk_error* error)
{
    const cvk_collide* c = s->collide;
    if (scene->collision.allow_intersecting_start || c->collider_count == 0)
        return CVK_SUCCESS;
    const cvk_build* b = &s->build;
    for (uint32_t p = 0; p < b->free_count; p++) {
        const float* x = &b->position[3 * (size_t)p];
        uint32_t first = c->instance_of ? c->instance_of[p] * c->instance_colliders : 0;
        for (uint32_t k = first; k < first + c->instance_colliders; k++) {
            float d = cvk_collide_distance(c, k, 0.0, x, NULL);
            if (d < -c->thickness)
                return fail_inside(s, p, k, -d, error);
        }
    }
    return CVK_SUCCESS;
}

/* ---- colliders ---------------------------------------------------------------------------- */

static void collider_stats(cvk_sim* s, const float* xyz, cvk_sim_stats* st)
{
    const cvk_collide* c = s->collide;
    double t = (double)s->frames * s->params.substeps * s->params.dt;
    for (uint32_t p = 0; p < s->build.free_count; p++) {
        const float* x = &xyz[3 * (size_t)p];
        double nearest = INFINITY;
        uint32_t first = c->instance_of ? c->instance_of[p] * c->instance_colliders : 0;
        for (uint32_t k = first; k < first + c->instance_colliders; k++)
            nearest = fmin(nearest, cvk_collide_distance(c, k, t, x, NULL));
        if (nearest < c->thickness + CONTACT_MARGIN)
            st->collider_contacts++;
        if (-nearest > st->max_penetration)
            st->max_penetration = -nearest;
    }
}

/* ---- particle–triangle pairs -------------------------------------------------------------- */

/* Particle p (free) is a corner of triangle v or joined by a spring to one: the pair is close
   in the rest mesh and not a contact. */
static bool near_in_mesh(const cvk_build* b, uint32_t p, const uint32_t* v)
{
    if (p == v[0] || p == v[1] || p == v[2])
        return true;
    for (uint32_t s = 0; s < b->degree[p]; s++) {
        uint32_t q = b->adj_index[(size_t)s * b->free_count + p];
        if (q == v[0] || q == v[1] || q == v[2])
            return true;
    }
    return false;
}

static bool finite3(const float* x)
{
    return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]);
}

/* The boxes of the pair search: the live, finite triangles grown by the thickness (rounded
   outwards, so that no particle within it falls outside), then the finite free particles as
   points. */
typedef struct self_query {
    const cvk_build* build;
    const uint32_t* instance_of; /* per particle, or NULL */
    const float* xyz;
    const uint32_t* tri;
    double thickness;
    uint32_t triangles;          /* boxes [0, triangles) are triangles, the rest particles */
    uint32_t* item;              /* per box: its triangle or particle */
    uint64_t pairs;
} self_query;

/* A triangle's box i and a particle's j within the thickness (cvk_box_pair_fn). */
static void self_pair(void* user, uint32_t i, uint32_t j)
{
    self_query* q = user;
    const uint32_t* v = &q->tri[3 * (size_t)q->item[i]];
    uint32_t p = q->item[j];
    if (near_in_mesh(q->build, p, v) || (q->instance_of && q->instance_of[p] != q->instance_of[v[0]]))
        return; /* copies never touch one another */
    double x[3], corner[3][3];
    for (int c = 0; c < 3; c++) {
        x[c] = q->xyz[3 * (size_t)p + c];
        for (int k = 0; k < 3; k++)
            corner[k][c] = q->xyz[3 * (size_t)v[k] + c];
    }
    if (cvk_point_triangle_distance2(x, corner[0], corner[1], corner[2]) <
        q->thickness * q->thickness)
        q->pairs++;
}

static cvk_result self_stats(cvk_sim* s, const float* xyz, const uint32_t* tri, cvk_sim_stats* st,
                             cvk_error* error)
{
    const cvk_build* b = &s->build;
    size_t n = (size_t)b->triangle_count + b->free_count;
    self_query q = {.build = b, .instance_of = s->collide->instance_of, .xyz = xyz, .tri = tri,
                    .thickness = s->collide->thickness};
    q.item = malloc((n ? n : 1) * sizeof *q.item);
    float* box = malloc(6 * (n ? n : 1) * sizeof *box);
    if (!q.item || !box) {
        free(q.item);
        free(box);
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY,
                        "contact statistics: out of host memory for %zu triangles and particles", n);
    }
    uint32_t count = 0;
    for (uint32_t t = 0; t < b->triangle_count; t++) {
        const uint32_t* v = &tri[3 * (size_t)t];
        if ((v[0] == v[1] && v[1] == v[2]) || !finite3(&xyz[3 * (size_t)v[0]]) ||
            !finite3(&xyz[3 * (size_t)v[1]]) || !finite3(&xyz[3 * (size_t)v[2]]))
            continue; /* torn, or lost */
        float* bx = &box[6 * (size_t)count];
        for (int c = 0; c < 3; c++) {
            double lo = INFINITY, hi = -INFINITY;
            for (int k = 0; k < 3; k++) {
                lo = fmin(lo, xyz[3 * (size_t)v[k] + c]);
                hi = fmax(hi, xyz[3 * (size_t)v[k] + c]);
            }
            bx[c] = nextafterf((float)(lo - q.thickness), -INFINITY);
            bx[3 + c] = nextafterf((float)(hi + q.thickness), INFINITY);
        }
        q.item[count++] = t;
    }
    q.triangles = count;
    for (uint32_t p = 0; p < b->free_count; p++) {
        const float* x = &xyz[3 * (size_t)p];
        if (!finite3(x))
            continue;
        memcpy(&box[6 * (size_t)count], x, 3 * sizeof(float));
        memcpy(&box[6 * (size_t)count + 3], x, 3 * sizeof(float));
        q.item[count++] = p;
    }
    cvk_result r = q.triangles == 0 ? CVK_SUCCESS
                                    : cvk_box_pairs(box, count, q.triangles, self_pair, &q,
                                                    "contact statistics", error);
    st->self_contacts = q.pairs;
    free(q.item);
    free(box);
    return r;
}

cvk_result cvk_sim_contact_stats(cvk_sim* s, const float* xyz_internal, cvk_sim_stats* st,
                                 cvk_error* error)
{
    st->collider_contacts = 0;
    st->self_contacts = 0;
    st->max_penetration = 0.0;
    st->intersecting_pairs = 0;
    st->contact_searches = 0;
    st->contact_held = 0;
    st->contact_held_fraction = 0.0;
    st->contact_crowded = 0;
    st->contact_cut = false;
    if (!s->collide->colliding)
        return CVK_SUCCESS;
    cvk_result searched =
        cvk_collide_counts(s, &st->contact_searches, &st->contact_held,
                           &st->contact_held_fraction, &st->contact_crowded, &st->contact_cut, error);
    if (searched != CVK_SUCCESS)
        return searched;
    collider_stats(s, xyz_internal, st);
    uint32_t* tri = NULL;
    cvk_result r = live_triangles(s, &tri, error);
    if (r == CVK_SUCCESS && s->collide->self)
        r = self_stats(s, xyz_internal, tri, st, error);
    uint32_t* groups = NULL;
    if (r == CVK_SUCCESS)
        r = cvk_collide_triangle_instances(&s->build, s->collide->instance_count, &groups, error);
    if (r == CVK_SUCCESS)
        r = cvk_count_intersecting_pairs(xyz_internal, s->build.particle_count, tri, groups,
                                         s->build.triangle_count, &st->intersecting_pairs, error);
    free(groups);
    free(tri);
    return r;
}
