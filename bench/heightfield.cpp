// The cost of a heightfield's contacts against a plane's: 1,000 bodies
// (boxes and spheres alternating) resting on a 1025 x 1025-sample field
// (1024 x 1024 cells) and the same bodies on a flat plane. Reports the
// narrow phase alone (collide() of each resting body with the ground, as the
// step calls it) and the step's collide phase (broad phase included), best of
// several rounds, and the ratios (docs/benchmarks.md, docs/terrain.md).
// Run: build/release/bench/bench_heightfield [--rounds N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;

namespace {

constexpr std::uint32_t kSamples = 1025;
constexpr Real kSpacing = Real(0.25);
constexpr int kBodies = 1000;
constexpr Real kDt = Real(1) / 60;

enum class Ground { Plane, FlatField, HillyField, SmallFlatField };

const char* name(Ground g) {
    switch (g) {
        case Ground::Plane: return "plane";
        case Ground::FlatField: return "flat heightfield 1024x1024";
        case Ground::HillyField: return "hilly heightfield 1024x1024";
        case Ground::SmallFlatField: return "flat heightfield 32x32 per body";
    }
    return "";
}

struct Setup {
    World world;
    BodyId ground;
    std::vector<BodyId> fields;  // the small fields, one per body
    std::vector<BodyId> bodies;
};

// Bodies on a 32 x 32 grid, 7.5 m apart, over the middle of the field.
Vec3 bodyPosition(int i) {
    const Real step = Real(7.5);
    return {static_cast<Real>(i % 32) * step - Real(116), 3, static_cast<Real>(i / 32) * step - Real(116)};
}

Real hill(Real x, Real z) { return Real(0.4) * std::sin(Real(0.15) * x) * std::cos(Real(0.11) * z); }

Setup build(Ground g) {
    WorldDef def;
    def.sleeping = false;  // every body collides every step
    Setup s{World(def), {}, {}, {}};
    BodyDef gd;
    gd.type = BodyType::Static;
    if (g == Ground::Plane) {
        gd.shape = Shape::plane({0, 1, 0}, 0);
        s.ground = s.world.createBody(gd);
    } else if (g == Ground::SmallFlatField) {
        // One 33 x 33 field (8 m) under each body: the same contacts, small fields.
        std::vector<Real> heights(33 * 33, 0);
        gd.shape = Shape::heightField(33, 33, kSpacing, kSpacing, heights);
        for (int i = 0; i < kBodies; ++i) {
            gd.position = bodyPosition(i) - Vec3{4, 3, 4};
            s.fields.push_back(s.world.createBody(gd));
        }
    } else {
        std::vector<Real> heights(std::size_t(kSamples) * kSamples, 0);
        const Real half = kSpacing * static_cast<Real>(kSamples - 1) / 2;
        if (g == Ground::HillyField) {
            for (std::uint32_t r = 0; r < kSamples; ++r) {
                for (std::uint32_t c = 0; c < kSamples; ++c) {
                    heights[std::size_t(r) * kSamples + c] =
                        hill(static_cast<Real>(c) * kSpacing - half, static_cast<Real>(r) * kSpacing - half);
                }
            }
        }
        gd.shape = Shape::heightField(kSamples, kSamples, kSpacing, kSpacing, heights);
        gd.position = {-half, 0, -half};
        s.ground = s.world.createBody(gd);
    }
    for (int i = 0; i < kBodies; ++i) {
        BodyDef d;
        d.shape = (i % 2 == 0) ? Shape::box(Vec3::splat(Real(0.25))) : Shape::sphere(Real(0.25));
        d.density = 1000;
        d.position = bodyPosition(i);
        d.position.y += g == Ground::HillyField ? hill(d.position.x, d.position.z) : 0;
        d.rollingResistance = Real(0.3);
        d.linearDamping = Real(0.5);
        d.angularDamping = Real(0.5);
        s.bodies.push_back(s.world.createBody(d));
    }
    for (int i = 0; i < 180; ++i) s.world.step(kDt);  // settle
    return s;
}

double seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }

struct Figures {
    double narrowPerBody = 0;  // s per collide() call
    double collidePerStep = 0;  // ms of the step's collide phase (StepProfile is in ms)
    std::size_t manifolds = 0, points = 0;
};

Figures measure(Setup& s, Ground g, int rounds) {
    Figures f;
    const Real margin = s.world.settings().speculativeMargin;
    ManifoldBuffer out;
    // The resting poses, and each body's ground (the field under it for the small fields).
    std::vector<Transform> poses;
    std::vector<BodyId> grounds;
    for (int i = 0; i < kBodies; ++i) {
        poses.push_back(s.world.transform(s.bodies[i]));
        grounds.push_back(g == Ground::SmallFlatField ? s.fields[static_cast<std::size_t>(i)] : s.ground);
    }
    double best = 1e30;
    for (int round = 0; round < rounds; ++round) {
        const auto t0 = std::chrono::steady_clock::now();
        constexpr int kRepeats = 20;
        for (int k = 0; k < kRepeats; ++k) {
            for (int i = 0; i < kBodies; ++i) {
                collide(s.world.shape(s.bodies[i]), poses[i], s.world.shape(grounds[i]), s.world.transform(grounds[i]), margin, out);
                if (k == 0 && round == 0) {
                    f.manifolds += out.size();
                    for (std::size_t m = 0; m < out.size(); ++m) f.points += out[m].pointCount;
                }
            }
        }
        best = std::min(best, seconds(std::chrono::steady_clock::now() - t0) / (kRepeats * kBodies));
    }
    f.narrowPerBody = best;
    best = 1e30;
    for (int round = 0; round < rounds; ++round) {
        double sum = 0;
        for (int i = 0; i < 30; ++i) {
            s.world.step(kDt);
            sum += s.world.lastStepProfile().collide;
        }
        best = std::min(best, sum / 30);
    }
    f.collidePerStep = best;
    return f;
}

}  // namespace

int main(int argc, char** argv) {
    int rounds = 5;
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--rounds") == 0) rounds = std::max(1, std::atoi(argv[i + 1]));
    }
    std::printf("%d bodies (boxes and spheres of 0.25 m), %u x %u samples at %.2f m; best of %d rounds\n", kBodies, kSamples,
                kSamples, double(kSpacing), rounds);
    std::printf("%-34s %14s %16s %10s %8s\n", "ground", "narrow ns/body", "collide ms/step", "manifolds", "points");
    Figures plane;
    for (Ground g : {Ground::Plane, Ground::FlatField, Ground::HillyField, Ground::SmallFlatField}) {
        const auto t0 = std::chrono::steady_clock::now();
        Setup s = build(g);
        const double buildSeconds = seconds(std::chrono::steady_clock::now() - t0);
        const Figures f = measure(s, g, rounds);
        if (g == Ground::Plane) plane = f;
        std::printf("%-34s %14.1f %16.3f %10zu %8zu   (x%.2f narrow, x%.2f collide; built and settled in %.1f s)\n", name(g),
                    f.narrowPerBody * 1e9, f.collidePerStep, f.manifolds, f.points, f.narrowPerBody / plane.narrowPerBody,
                    f.collidePerStep / plane.collidePerStep, buildSeconds);
    }
    return 0;
}
