#pragma once
// Bytes per body and per contact in Fulcrum (bench_benchmark_scenes --sizes):
//  - sizeof of the per-body tiers of src/world/world_impl.hpp (hot motion,
//    warm params, cold) and of the per-contact records (the narrow phase's
//    manifold, the contact cache's manifold, the solver's contact constraint);
//  - measured heap in use (glibc mallinfo2) per body and per contact, which
//    includes everything the engine keeps (broad-phase proxies, solver
//    scratch, vector capacity slack).
#include <malloc.h>

#include <cstdio>
#include <vector>

#include "collision/manifold.hpp"
#include "fulcrum/fulcrum.hpp"
#include "contacts/contact.hpp"
#include "solver/contact_solver.hpp"
#include "world/world_impl.hpp"

namespace bench {

inline double heapInUse() { return static_cast<double>(mallinfo2().uordblks); }

// Heap bytes a world of `n` unit boxes holds after `steps` steps: in a grid
// 3 m apart (no contacts) or stacked in columns of 10 (resting contacts).
struct HeapFigure {
    double bytes = 0;
    std::size_t manifolds = 0, points = 0;
};
inline HeapFigure heapOfBoxes(int n, bool stacked, int steps) {
    const double before = heapInUse();
    HeapFigure f;
    {
        fulcrum::WorldDef def;
        def.sleeping = false;
        fulcrum::World world(def);
        fulcrum::BodyDef ground;
        ground.type = fulcrum::BodyType::Static;
        ground.shape = fulcrum::Shape::box({200, 0.5f, 200});
        ground.position = {0, -0.5f, 0};
        world.createBody(ground);
        const fulcrum::Shape box = fulcrum::Shape::box({0.5f, 0.5f, 0.5f});
        for (int i = 0; i < n; ++i) {
            fulcrum::BodyDef d;
            d.shape = box;
            d.mass = 1;
            const int column = stacked ? i / 10 : i, level = stacked ? i % 10 : 0;
            d.position = {static_cast<float>(3 * (column % 40)), 0.5f + static_cast<float>(level) + (stacked ? 0 : 5.0f),
                          static_cast<float>(3 * (column / 40))};
            world.createBody(d);
        }
        for (int s = 0; s < steps; ++s) world.step(1.0f / 60);
        f.bytes = heapInUse() - before;
        for (const fulcrum::ContactReport& c : world.contacts()) {
            ++f.manifolds;
            f.points += c.points.size();
        }
    }
    return f;
}

inline void printMemorySizes() {
    using namespace fulcrum::detail;
    std::printf("\n### Bytes per body and per contact (Fulcrum)\n\n");
    std::printf("| record | bytes |\n|---|---|\n");
    std::printf("| body, hot: BodyMotion (centre of mass, orientation, velocities, inverse mass and world inverse inertia) | %zu |\n",
                sizeof(BodyMotion));
    std::printf("| body, hot scratch: ForceTorque x 2 (forces, applied) + IntegratorScratch | %zu |\n",
                2 * sizeof(ForceTorque) + sizeof(IntegratorScratch));
    std::printf("| body, warm: BodyParams | %zu |\n", sizeof(BodyParams));
    std::printf("| body, cold: BodyCold (name, shape, callback) + previous Transform + slot + dense-to-slot | %zu |\n",
                sizeof(BodyCold) + sizeof(fulcrum::Transform) + sizeof(BodySlot) + sizeof(std::uint32_t));
    std::printf("| body, solver: SolverBody | %zu |\n", sizeof(SolverBody));
    std::printf("| contact: narrow-phase Manifold (up to 4 points) | %zu |\n", sizeof(fulcrum::Manifold));
    std::printf("| contact: cached manifold (warm starting) | %zu |\n", sizeof(CachedManifold));
    std::printf("| contact: pair record (Contact) | %zu |\n", sizeof(Contact));
    std::printf("| contact: solver ContactConstraint (one manifold) | %zu |\n", sizeof(ContactConstraint));

    // Heap: 4000 boxes apart vs 4000 boxes in 400 resting columns of 10.
    const int n = 4000;
    const HeapFigure empty = heapOfBoxes(0, false, 2);
    const HeapFigure apart = heapOfBoxes(n, false, 2);
    const HeapFigure stacked = heapOfBoxes(n, true, 30);
    const double perBody = (apart.bytes - empty.bytes) / n;
    std::printf("| measured heap per body (%d boxes apart, after 2 steps; all engine arrays incl. broad phase and slack) | %.0f |\n",
                n, perBody);
    if (stacked.manifolds > 0) {
        const double extra = stacked.bytes - apart.bytes;
        std::printf("| measured heap per touching manifold (same boxes stacked 10 high: %zu manifolds, %zu points) | %.0f (%.0f per point) |\n",
                    stacked.manifolds, stacked.points, extra / static_cast<double>(stacked.manifolds),
                    extra / static_cast<double>(stacked.points));
    }
    std::fflush(stdout);
}

}  // namespace bench
