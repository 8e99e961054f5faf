// Stand-alone timing of a moving tree's descent against itself
// (DynamicTree::overlapPairs), as HighSpeed's broad phase runs it: COUNT
// boxes of 1.2 m at up to 250 m/s in a 100 m box, fattened along a step's
// motion (1/60 s), rebuilt once and refitted over WARM steps. Then, REPS
// times: the refit (refitOrRebuild, which writes the depth-first copy of a
// large tree as it goes), the descent over the node pool (the copy made out
// of date), the copy alone (prepareSelfDescent) and the descent over it; the
// minimum of each (wall clock; the machine is shared, so only minima of
// many repetitions mean anything). Not a test: it also checks that both
// descents call back the same pairs in the same order.
//   build-bench/bench/bench_tree_descent [COUNT] [REPS] [WARM]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "collision/dynamic_tree.hpp"

using namespace fulcrum;

namespace {
double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
    const int count = argc > 1 ? std::atoi(argv[1]) : 5000;
    const int reps = argc > 2 ? std::atoi(argv[2]) : 300;
    const int warm = argc > 3 ? std::atoi(argv[3]) : 8;
    if (count <= 0 || reps <= 0 || warm < 0) {
        std::fprintf(stderr, "usage: %s [COUNT] [REPS] [WARM]\n", argv[0]);
        return 2;
    }
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> pos(-49, 49), dir(-1, 1), speed(0, 250);
    const Real dt = Real(1) / 60, half = Real(0.6);
    std::vector<Vec3> centre(static_cast<std::size_t>(count)), velocity(static_cast<std::size_t>(count));
    std::vector<std::int32_t> ids(static_cast<std::size_t>(count));
    DynamicTree tree;
    for (std::size_t i = 0; i < centre.size(); ++i) {
        centre[i] = Vec3{pos(rng), pos(rng), pos(rng)};
        Vec3 d{dir(rng), dir(rng), dir(rng)};
        const Real len = length(d);
        velocity[i] = len > Real(1e-3) ? d * (speed(rng) / len) : Vec3{speed(rng), 0, 0};
        ids[i] = tree.createProxy(AABB::fromCenterHalf(centre[i], Vec3::splat(half)), static_cast<std::uint32_t>(i),
                                  velocity[i] * dt);
    }
    const auto advance = [&] {
        for (std::size_t i = 0; i < centre.size(); ++i) {
            for (std::size_t a = 0; a < 3; ++a) {
                Real c = centre[i][a] + velocity[i][a] * dt;
                if (c > Real(49.4) || c < Real(-49.4)) {  // the walls: restitution 1
                    velocity[i][a] = -velocity[i][a];
                    c = std::clamp(c, Real(-49.4), Real(49.4));
                }
                centre[i][a] = c;
            }
            tree.setFatBox(ids[i], AABB::fromCenterHalf(centre[i], Vec3::splat(half)), velocity[i] * dt);
        }
    };
    for (int s = 0; s < warm; ++s) {
        advance();
        tree.refitOrRebuild();
    }
    double refit = 1e30, pool = 1e30, copy = 1e30, walk = 1e30;
    std::size_t pairs = 0;
    std::uint64_t orderPool = 0, orderCopy = 0;
    for (int r = 0; r < reps; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        tree.refitOrRebuild();  // nothing moved: a refit (which writes the copy for a large tree)
        refit = std::min(refit, seconds(t0));
        // The same box again: nothing changes but the copy is out of date, so the pool is walked.
        tree.setFatBox(ids[0], AABB::fromCenterHalf(centre[0], Vec3::splat(half)), velocity[0] * dt);
        tree.reinsert(ids[0]);
        std::size_t n = 0;
        std::uint64_t h = 1469598103934665603ull;
        t0 = std::chrono::steady_clock::now();
        tree.overlapPairs(tree.root(), tree, tree.root(), [&](std::uint32_t a, std::uint32_t b) {
            h = (h ^ (std::uint64_t{a} << 32 | b)) * 1099511628211ull;
            ++n;
            return true;
        });
        pool = std::min(pool, seconds(t0));
        pairs = n;
        orderPool = h;
        t0 = std::chrono::steady_clock::now();
        tree.prepareSelfDescent();
        copy = std::min(copy, seconds(t0));
        if (!tree.selfDescentPrepared() && count >= DynamicTree::kBranchFreeDescentLeaves) {
            std::fprintf(stderr, "no copy made\n");
            return 1;
        }
        n = 0;
        h = 1469598103934665603ull;
        t0 = std::chrono::steady_clock::now();
        tree.overlapPairs(tree.root(), tree, tree.root(), [&](std::uint32_t a, std::uint32_t b) {
            h = (h ^ (std::uint64_t{a} << 32 | b)) * 1099511628211ull;
            ++n;
            return true;
        });
        walk = std::min(walk, seconds(t0));
        orderCopy = h;
        if (n != pairs || orderCopy != orderPool) {
            std::fprintf(stderr, "the copy's descent differs: %zu pairs against %zu\n", n, pairs);
            return 1;
        }
    }
    std::printf("%d boxes, %zu overlapping pairs, height %d; min of %d (us): refit %.1f, descent over the pool %.1f, "
                "copy %.1f, descent over the copy %.1f, copy + its descent %.1f (%+.1f %%)\n",
                count, pairs, tree.height(), reps, refit * 1e6, pool * 1e6, copy * 1e6, walk * 1e6,
                (copy + walk) * 1e6, 100.0 * ((copy + walk) / pool - 1));
    return 0;
}
