// Side-by-side scene benchmark: docs/benchmark-scenes.md's pyramid20,
// pyramid_large, box_pile and sphere_pile in Fulcrum and (when built with it)
// Bullet 3, in the same run. scripts/bench.sh builds and runs it.
//
//   bench_benchmark_scenes [--quick] [--scene NAME] [--fulcrum-only] [--threads N]
//
// Per scene and engine: median and mean ms per step, mean over the first 120
// steps, total seconds, the quality metric (worst horizontal drift and top box
// sink for pyramids; bodies asleep and deepest penetration for all), and
// Fulcrum's mean time as a ratio of Bullet's.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <string>

#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"
#ifdef FULCRUM_HAVE_BULLET
#include "peers/bullet_scenes.hpp"
#endif

namespace {

using bench::BodySpec;
using bench::RunResult;
using bench::SceneSpec;

RunResult runFulcrum(const SceneSpec& scene, int threads) {
    RunResult r;
    r.ran = true;
    fulcrum::WorldDef def;
    def.sleeping = scene.sleeping;
    def.threads = threads;
    fulcrum::World world(def);
    std::vector<fulcrum::BodyId> ids;
    const fulcrum::Shape unitBox = fulcrum::Shape::box({0.5f, 0.5f, 0.5f});
    const fulcrum::Shape sphere = fulcrum::Shape::sphere(0.5f);
    for (const BodySpec& b : scene.bodies) {
        fulcrum::BodyDef d;
        d.type = b.isStatic ? fulcrum::BodyType::Static : fulcrum::BodyType::Dynamic;
        if (b.kind == BodySpec::Kind::Sphere) {
            d.shape = b.hx == 0.5f ? sphere : fulcrum::Shape::sphere(b.hx);
        } else {
            d.shape = (b.hx == 0.5f && b.hy == 0.5f && b.hz == 0.5f) ? unitBox : fulcrum::Shape::box({b.hx, b.hy, b.hz});
        }
        if (!b.isStatic) d.mass = b.mass;
        d.position = {b.x, b.y, b.z};
        d.friction = scene.friction;  // geometric mean of equal values: the pair value
        ids.push_back(world.createBody(d));
    }
    std::vector<fulcrum::Vec3> start;
    for (fulcrum::BodyId id : ids) start.push_back(world.position(id));
    r.stepMs.reserve(static_cast<std::size_t>(scene.steps));
    for (int i = 0; i < scene.steps; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        world.step(scene.dt);
        const auto t1 = std::chrono::steady_clock::now();
        r.stepMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if (scene.bodies[i].isStatic) continue;
        const fulcrum::Vec3 p = world.position(ids[i]);
        const double dx = p.x - start[i].x, dz = p.z - start[i].z;
        r.drift = std::max(r.drift, std::sqrt(dx * dx + dz * dz));
        if (!world.isAwake(ids[i])) ++r.asleep;
    }
    if (scene.topIndex >= 0) {
        const auto top = static_cast<std::size_t>(scene.topIndex);
        r.sink = start[top].y - world.position(ids[top]).y;
    }
    for (const fulcrum::ContactReport& c : world.contacts()) r.penetration = std::max(r.penetration, double(c.depth));
    return r;
}

double mean(const std::vector<double>& v, std::size_t count) {
    count = std::min(count, v.size());
    if (count == 0) return 0;
    return std::accumulate(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(count), 0.0) / static_cast<double>(count);
}
double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

void printRow(const SceneSpec& scene, const char* engine, const RunResult& r, double ratio) {
    const double total = std::accumulate(r.stepMs.begin(), r.stepMs.end(), 0.0) / 1000;
    std::printf("| %-18s | %-7s | %8.3f | %8.3f | %8.3f | %7.2f | ", scene.name.c_str(), engine, median(r.stepMs),
                mean(r.stepMs, r.stepMs.size()), mean(r.stepMs, 120), total);
    if (scene.pyramid) {
        const bool stands = r.drift < 0.05 && r.sink < 0.25;
        std::printf("%s: drift %.3f m, sink %.3f m; ", stands ? "stands" : "FAILS", r.drift, r.sink);
    }
    std::printf("asleep %d, deepest %.4f m | ", r.asleep, r.penetration);
    if (ratio > 0) {
        std::printf("%.2f |\n", ratio);
    } else {
        std::printf("- |\n");
    }
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false, fulcrumOnly = false;
    std::string only;
    int threads = 1;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        else if (std::strcmp(argv[i], "--fulcrum-only") == 0) fulcrumOnly = true;
        else if (std::strcmp(argv[i], "--scene") == 0 && i + 1 < argc) only = argv[++i];
        else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr, "usage: %s [--quick] [--scene NAME] [--fulcrum-only] [--threads N]\n", argv[0]);
            return 2;
        }
    }
    std::printf("| scene | engine | median ms | mean ms | first 120 ms | total s | quality | Fulcrum/Bullet |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const SceneSpec& scene : bench::allScenes(quick)) {
        if (!only.empty() && scene.name.rfind(only, 0) != 0) continue;
        const RunResult f = runFulcrum(scene, threads);
        RunResult b;
#ifdef FULCRUM_HAVE_BULLET
        if (!fulcrumOnly) b = bench::runBullet(scene);
#endif
        const double ratio = b.ran ? mean(f.stepMs, f.stepMs.size()) / mean(b.stepMs, b.stepMs.size()) : 0;
        printRow(scene, "Fulcrum", f, ratio);
        if (b.ran) printRow(scene, "Bullet", b, 0);
        std::fflush(stdout);
    }
    return 0;
}
