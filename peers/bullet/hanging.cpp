// clothvk's standard hanging cloth (assets/scenes/peer-hanging.json) in Bullet's soft body
// (btSoftBody): 100 x 100 nodes on a 1 m square, 0.1 kg, horizontal at y = 1 m, pinned at the
// two corners of one edge, structural links only, gravity 9.81 m/s^2, 120 frames of 1/60 s on
// one thread. Prints wall milliseconds per frame and, at the last frame, the same metrics over
// the structural links as clothvk-sim --json: residual sum (|xa - xb| - L)^2, largest stretch
// max(|xa - xb| / L - 1) and its 99th percentile (nearest rank, as lib/topology/metrics.c).
//
// Stiffness: Bullet's links take a linear stiffness coefficient kLST in [0, 1] (a fraction of
// the correction per position-solver iteration), not N/m; clothvk's 1e6 N/m springs are stiff
// enough to be inextensible at this scale, so the harness uses Bullet's stiffest setting,
// kLST = 1, with 256 position-solver iterations (piterations) per step.
//
// Usage: bullet-hanging [--grid N] [--frames F] [--iterations I] [--substeps S]
#include <btBulletDynamicsCommon.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btDefaultSoftBodySolver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

namespace {

struct options {
    int grid = 100;
    int frames = 120;
    int iterations = 256;
    int substeps = 1;
};

bool parse_int(const char* flag, const char* text, int lo, int hi, int* out)
{
    char* end = nullptr;
    long v = std::strtol(text, &end, 10);
    if (*text == '\0' || *end != '\0' || v < lo || v > hi) {
        std::fprintf(stderr, "bullet-hanging: %s wants an integer in [%d, %d], got '%s'\n", flag,
                     lo, hi, text);
        return false;
    }
    *out = (int)v;
    return true;
}

bool parse(int argc, char** argv, options* o)
{
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
        bool ok = true;
        if (!v) {
            std::fprintf(stderr, "bullet-hanging: %s wants a value\n", a);
            return false;
        }
        if (!std::strcmp(a, "--grid"))
            ok = parse_int(a, v, 2, 1000, &o->grid);
        else if (!std::strcmp(a, "--frames"))
            ok = parse_int(a, v, 1, 100000, &o->frames);
        else if (!std::strcmp(a, "--iterations"))
            ok = parse_int(a, v, 1, 100000, &o->iterations);
        else if (!std::strcmp(a, "--substeps"))
            ok = parse_int(a, v, 1, 1000, &o->substeps);
        else {
            std::fprintf(stderr, "bullet-hanging: unknown option %s\n", a);
            return false;
        }
        if (!ok)
            return false;
        i++;
    }
    return true;
}

struct metrics {
    double residual = 0, max_stretch = 0, p99_stretch = 0;
};

metrics measure(const btSoftBody* body)
{
    metrics m;
    std::vector<double> stretch;
    stretch.reserve(body->m_links.size());
    m.max_stretch = -INFINITY;
    for (int i = 0; i < body->m_links.size(); i++) {
        const btSoftBody::Link& l = body->m_links[i];
        double d = (l.m_n[0]->m_x - l.m_n[1]->m_x).length();
        double e = d / l.m_rl - 1.0;
        m.residual += (d - l.m_rl) * (d - l.m_rl);
        m.max_stretch = std::max(m.max_stretch, e);
        stretch.push_back(e);
    }
    std::sort(stretch.begin(), stretch.end());
    size_t rank = (size_t)std::ceil(0.99 * (double)stretch.size());
    m.p99_stretch = stretch.empty() ? 0.0 : stretch[(rank > 0 ? rank : 1) - 1];
    return m;
}

} // namespace

int main(int argc, char** argv)
{
    options o;
    if (!parse(argc, argv, &o))
        return 2;

    auto config = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
    auto dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
    auto broadphase = std::make_unique<btDbvtBroadphase>();
    auto solver = std::make_unique<btSequentialImpulseConstraintSolver>();
    auto world = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher.get(), broadphase.get(),
                                                            solver.get(), config.get());
    const btVector3 gravity(0, -9.81, 0);
    world->setGravity(gravity);
    btSoftBodyWorldInfo& info = world->getWorldInfo();
    info.m_gravity = gravity;
    info.air_density = 0; // clothvk's peer-hanging has no air
    info.m_sparsesdf.Initialize();

    // Node (i, j) = corner00 + i/(N-1) * u + j/(N-1) * v with u = +x, v = +z, as the scene's
    // grid; fixeds 1 + 2 pins corner00 and corner10: grid [0, 0] and [N-1, 0].
    btSoftBody* body = btSoftBodyHelpers::CreatePatch(
        info, btVector3(-0.5, 1, -0.5), btVector3(0.5, 1, -0.5), btVector3(-0.5, 1, 0.5),
        btVector3(0.5, 1, 0.5), o.grid, o.grid, 1 + 2, false);
    body->m_materials[0]->m_kLST = 1.0;
    body->m_cfg.piterations = o.iterations;
    body->m_cfg.kDP = 0;                           // no damping, as the scene
    body->m_cfg.collisions = 0;                    // nothing to collide with, no self-contact
    body->setTotalMass(0.1);
    world->addSoftBody(body);
    const int links = body->m_links.size();
    const int nodes = body->m_nodes.size();

    const double frame = 1.0 / 60.0;
    std::vector<double> ms(o.frames);
    auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < o.frames; f++) {
        auto t0 = std::chrono::steady_clock::now();
        world->stepSimulation(frame, o.substeps, frame / o.substeps);
        auto t1 = std::chrono::steady_clock::now();
        ms[f] = std::chrono::duration<double, std::milli>(t1 - t0).count();
    }
    double total_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    metrics m = measure(body);
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    double mean = total_s * 1e3 / o.frames;
    double median = sorted[sorted.size() / 2];
    bool finite = std::isfinite(m.residual) && std::isfinite(m.max_stretch);

    std::printf("bullet-hanging grid=%d nodes=%d links=%d frames=%d substeps=%d iterations=%d "
                "ms_per_frame_mean=%.2f ms_per_frame_median=%.2f residual=%.3g "
                "max_stretch=%.4f p99_stretch=%.4f finite=%s\n",
                o.grid, nodes, links, o.frames, o.substeps, o.iterations, mean, median,
                m.residual, m.max_stretch, m.p99_stretch, finite ? "yes" : "no");
    world->removeSoftBody(body);
    delete body;
    return finite ? 0 : 1;
}
