// Narrow-phase pairs per second for each shape-pair family, in resting
// (overlapping, multi-point) configurations: the common case in a settled scene.
// Run: build-bench/bench/bench_narrowphase --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <array>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "fulcrum/shape.hpp"

using namespace fulcrum;

namespace {

constexpr Real kMargin = Real(0.02);

Shape hullBox() {
    // A rounded-corner "box" hull with 24 vertices, closer to game content than 8.
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) {
        const Vec3 c{(i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f};
        p.push_back(c + Vec3{c.x > 0 ? 0.05f : -0.05f, 0, 0});
        p.push_back(c + Vec3{0, c.y > 0 ? 0.05f : -0.05f, 0});
        p.push_back(c + Vec3{0, 0, c.z > 0 ? 0.05f : -0.05f});
    }
    return Shape::convexHull(p);
}

Shape gridMesh(int n) {
    std::vector<Vec3> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) v.push_back({static_cast<Real>(i - n / 2), 0, static_cast<Real>(j - n / 2)});
    }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            t.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            t.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
        }
    }
    return Shape::mesh(v, t);
}

void runPair(benchmark::State& state, const Shape& a, const Transform& xa, const Shape& b, const Transform& xb) {
    ManifoldBuffer out;
    std::size_t points = 0;
    for (auto _ : state) {
        collide(a, xa, b, xb, kMargin, out);
        points += out.empty() ? 0 : out[0].pointCount;
        benchmark::DoNotOptimize(out);
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
    state.counters["points"] = static_cast<double>(points) / static_cast<double>(state.iterations());
}

const Quat kTilt = Quat::fromAxisAngle(normalize(Vec3{0.2f, 1, 0.1f}), 0.3f);

}  // namespace

static void SphereSphere(benchmark::State& s) { runPair(s, Shape::sphere(0.5f), {}, Shape::sphere(0.5f), {{0.3f, 0.95f, 0}, {}}); }
static void SphereBox(benchmark::State& s) { runPair(s, Shape::sphere(0.5f), {{0.2f, 0.99f, 0}, {}}, Shape::box({0.5f, 0.5f, 0.5f}), {}); }
static void CapsuleCapsule(benchmark::State& s) {
    runPair(s, Shape::capsule(0.2f, 0.5f), {}, Shape::capsule(0.2f, 0.5f), {{0.1f, 0.39f, 0}, kTilt});
}
static void CapsuleBox(benchmark::State& s) {
    runPair(s, Shape::capsule(0.2f, 0.5f), {{0.1f, 0.69f, 0}, Quat::fromAxisAngle({0, 0, 1}, 1.5707963f)},
            Shape::box({0.5f, 0.5f, 0.5f}), {});
}
static void BoxBox(benchmark::State& s) {
    runPair(s, Shape::box({0.5f, 0.5f, 0.5f}), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0.1f, 0.99f, 0.05f}, Quat::fromAxisAngle({0, 1, 0}, 0.3f)});
}
static void BoxPlane(benchmark::State& s) {
    runPair(s, Shape::plane({0, 1, 0}, 0), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0, 0.49f, 0}, kTilt});
}
static void HullHull(benchmark::State& s) {
    const Shape h = hullBox();
    runPair(s, h, {}, h, {{0.1f, 1.09f, 0.05f}, kTilt});
}
static void HullBox(benchmark::State& s) { runPair(s, hullBox(), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0.1f, 1.04f, 0}, kTilt}); }
static void CylinderBox(benchmark::State& s) {
    runPair(s, Shape::cylinder(0.5f, 0.5f), {{0.1f, 0.99f, 0}, {}}, Shape::box({1, 0.5f, 1}), {});
}
static void SphereMesh(benchmark::State& s) { runPair(s, Shape::sphere(0.5f), {{0.3f, 0.49f, 0.2f}, {}}, gridMesh(32), {}); }
static void BoxMesh(benchmark::State& s) {
    runPair(s, Shape::box({0.5f, 0.25f, 0.5f}), {{0.3f, 0.24f, 0.2f}, Quat::fromAxisAngle({0, 1, 0}, 0.4f)}, gridMesh(32), {});
}
static void HullMesh(benchmark::State& s) { runPair(s, hullBox(), {{0.3f, 0.54f, 0.2f}, {}}, gridMesh(32), {}); }

BENCHMARK(SphereSphere);
BENCHMARK(SphereBox);
BENCHMARK(CapsuleCapsule);
BENCHMARK(CapsuleBox);
BENCHMARK(BoxBox);
BENCHMARK(BoxPlane);
BENCHMARK(HullHull);
BENCHMARK(HullBox);
BENCHMARK(CylinderBox);
BENCHMARK(SphereMesh);
BENCHMARK(BoxMesh);
BENCHMARK(HullMesh);
BENCHMARK_MAIN();
