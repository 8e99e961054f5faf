// Batch throughput (docs/benchmarks.md, "Batches"): world-steps per second of
// N copies of ten_boxes or pyramid20 (bench/scenes.hpp) stepped as a
// fulcrum::Batch, against the same steps as one C++ loop of World::step calls,
// and the heap each world of a batch holds.
//
//   bench_batch SCENE N THREADS STEPS MODE
//     SCENE: ten | pyramid20;  MODE: batch | loop (one thread, world after world)
//
// Prints one line: scene, N, threads, mode, world-steps/s, heap bytes per world.
// A plain program (no Google Benchmark loop) so callgrind can count one run.
#include <malloc.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fulcrum/batch.hpp"
#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"

namespace {

fulcrum::Vec3 fv(bench::V3 v) {
    return {static_cast<fulcrum::Real>(v.x), static_cast<fulcrum::Real>(v.y), static_cast<fulcrum::Real>(v.z)};
}

// The bodies of a box scene (both scenes here are boxes on a static box ground).
fulcrum::World build(const bench::SceneSpec& scene) {
    fulcrum::WorldDef def;
    def.sleeping = scene.sleeping;
    def.gravity = fv(scene.gravity);
    fulcrum::World world(def);
    for (const bench::BodySpec& b : scene.bodies) {
        fulcrum::BodyDef d;
        d.type = b.isStatic ? fulcrum::BodyType::Static : fulcrum::BodyType::Dynamic;
        d.shape = fulcrum::Shape::box(fv(b.half));
        if (!b.isStatic) d.mass = static_cast<fulcrum::Real>(b.mass);
        d.position = fv(b.position);
        d.friction = static_cast<fulcrum::Real>(scene.friction);
        world.createBody(d);
    }
    return world;
}

double heap() { return static_cast<double>(mallinfo2().uordblks); }

}  // namespace

int main(int argc, char** argv) {
    if (argc != 6) {
        std::fprintf(stderr, "usage: bench_batch ten|pyramid20 N THREADS STEPS batch|loop\n");
        return 2;
    }
    const std::string name = argv[1], mode = argv[5];
    const int n = std::atoi(argv[2]), threads = std::atoi(argv[3]), steps = std::atoi(argv[4]);
    const bench::SceneSpec scene = name == "ten" ? bench::tenBoxes() : bench::pyramid("pyramid20", 20, steps);
    const auto dt = static_cast<fulcrum::Real>(scene.dt);

    const double before = heap();
    std::vector<fulcrum::World> worlds;
    worlds.reserve(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) worlds.push_back(build(scene));
    double seconds = 0;
    double bytes = 0;
    using Clock = std::chrono::steady_clock;
    if (mode == "batch") {
        fulcrum::Batch batch(std::move(worlds), fulcrum::BatchDef{threads});
        batch.step(dt, 1);  // first step: contact caches and scratch grow
        bytes = (heap() - before) / n;
        const auto t0 = Clock::now();
        batch.step(dt, steps);
        seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    } else {
        for (auto& w : worlds) w.step(dt);
        bytes = (heap() - before) / n;
        const auto t0 = Clock::now();
        for (auto& w : worlds)
            for (int s = 0; s < steps; ++s) w.step(dt);
        seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    std::printf("%s N=%d threads=%d %s: %.0f world-steps/s, %.0f heap bytes per world\n", name.c_str(), n, threads,
                mode.c_str(), static_cast<double>(n) * steps / seconds, bytes);
    return 0;
}
