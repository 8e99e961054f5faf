// Joint benchmark: the `chain` of bench/scenes.hpp (docs/benchmarks.md), a pile of 100 ragdolls
// (11 bodies each) on the ground, and a 30 x 30 x 30 grid of spheres joined by
// ball joints to their neighbours below and beside, hanging from the top layer.
//
//   bench_joints [--quick] [--scene chain|ragdolls|grid] [--gauss-seidel] [--steps N] [--threads N] [--markdown]
//
// --markdown prints the results as the Markdown table that scripts/bench.sh
// --write-docs puts into docs/benchmarks.md (so its figures are never typed in).
//
// Per scene: median and mean ms per step, and the quality metric: the worst
// joint error (m) over the run and at the end, and the bodies asleep at the
// end. World defaults (5 sub-steps, 1 iteration); --gauss-seidel turns the
// joint-tree solver off (WorldDef::jointDirectSolve) for comparison. Ragdoll
// joints carry 0.5 N m of friction (JointDef::frictionTorque), as in the
// ragdoll test. Results are in docs/joints.md.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include "fulcrum/fulcrum.hpp"

namespace {

using namespace fulcrum;

struct Scene {
    std::string name;
    World world;
    std::vector<JointId> joints;
    int steps = 600;
    explicit Scene(std::string n, const WorldDef& d = {}) : name(std::move(n)), world(d) {}
};

void buildChain(Scene& s) {
    BodyId prev = kWorldBody;
    for (int i = 0; i < 100; ++i) {
        BodyDef b;
        b.shape = Shape::capsule(Real(0.1), Real(0.4));
        b.mass = 1;
        b.position = {Real(0.5) + static_cast<Real>(i), 60, 0};
        b.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
        const BodyId id = s.world.createBody(b);
        JointDef j;
        j.type = JointType::Ball;
        j.bodyA = prev;
        j.bodyB = id;
        j.anchor = {static_cast<Real>(i), 60, 0};
        s.joints.push_back(s.world.createJoint(j));
        prev = id;
    }
}

BodyId addBody(Scene& s, const Shape& shape, Real mass, Vec3 p, Quat q = {}) {
    BodyDef d;
    d.shape = shape;
    d.mass = mass;
    d.position = p;
    d.orientation = q;
    d.angularDamping = Real(0.5);
    return s.world.createBody(d);
}

void joint(Scene& s, JointType t, BodyId a, BodyId b, Vec3 p, Vec3 axis, Real lo, Real hi, Real swing = 0) {
    JointDef j;
    j.type = t;
    j.bodyA = a;
    j.bodyB = b;
    j.anchor = p;
    j.axis = axis;
    if (t == JointType::Hinge) {
        j.hasLimits = true;
        j.lowerLimit = lo;
        j.upperLimit = hi;
    } else {
        j.swingLimit = swing;
        j.twistLower = lo;
        j.twistUpper = hi;
    }
    j.frictionTorque = Real(0.5);
    s.joints.push_back(s.world.createJoint(j));
}

void addRagdoll(Scene& s, Vec3 o) {
    const Quat side = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
    const BodyId pelvis = addBody(s, Shape::box({Real(0.15), Real(0.1), Real(0.1)}), 8, o + Vec3{0, 1, 0});
    const BodyId torso = addBody(s, Shape::box({Real(0.18), Real(0.22), Real(0.1)}), 15, o + Vec3{0, Real(1.35), 0});
    const BodyId head = addBody(s, Shape::sphere(Real(0.11)), 4, o + Vec3{0, Real(1.72), 0});
    joint(s, JointType::ConeTwist, pelvis, torso, o + Vec3{0, Real(1.1), 0}, {0, 1, 0}, Real(-0.3), Real(0.3), Real(0.4));
    joint(s, JointType::ConeTwist, torso, head, o + Vec3{0, Real(1.59), 0}, {0, 1, 0}, Real(-0.8), Real(0.8), Real(0.6));
    for (const Real k : {Real(-1), Real(1)}) {
        const BodyId ua = addBody(s, Shape::capsule(Real(0.05), Real(0.1)), 2, o + Vec3{k * Real(0.38), Real(1.5), 0}, side);
        const BodyId la = addBody(s, Shape::capsule(Real(0.045), Real(0.1)), Real(1.5), o + Vec3{k * Real(0.66), Real(1.5), 0}, side);
        joint(s, JointType::ConeTwist, torso, ua, o + Vec3{k * Real(0.24), Real(1.5), 0}, {k, 0, 0}, Real(-0.5), Real(0.5), Real(1.2));
        joint(s, JointType::Hinge, ua, la, o + Vec3{k * Real(0.52), Real(1.5), 0}, {0, 1, 0}, 0, Real(2.5));
        const BodyId th = addBody(s, Shape::capsule(Real(0.07), Real(0.13)), 7, o + Vec3{k * Real(0.1), Real(0.7), 0});
        const BodyId sh = addBody(s, Shape::capsule(Real(0.06), Real(0.15)), 4, o + Vec3{k * Real(0.1), Real(0.27), 0});
        joint(s, JointType::ConeTwist, pelvis, th, o + Vec3{k * Real(0.1), Real(0.9), 0}, {0, -1, 0}, Real(-0.3), Real(0.3), Real(0.8));
        joint(s, JointType::Hinge, th, sh, o + Vec3{k * Real(0.1), Real(0.49), 0}, {1, 0, 0}, Real(-2.5), 0);
    }
}

void buildRagdolls(Scene& s) {
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::box({40, Real(0.5), 40});
    g.position = {0, Real(-0.5), 0};
    s.world.createBody(g);
    // 5 x 5 columns, 4 high, 2 m apart: they fall onto each other.
    for (int layer = 0; layer < 4; ++layer) {
        for (int i = 0; i < 5; ++i) {
            for (int k = 0; k < 5; ++k) {
                addRagdoll(s, {static_cast<Real>(i - 2) * 2, 1 + Real(2.2) * static_cast<Real>(layer), static_cast<Real>(k - 2) * Real(1.2)});
            }
        }
    }
}

void buildGrid(Scene& s, int n) {
    std::vector<BodyId> ids(static_cast<std::size_t>(n * n * n));
    auto at = [&](int x, int y, int z) -> BodyId& { return ids[static_cast<std::size_t>((y * n + z) * n + x)]; };
    for (int y = 0; y < n; ++y) {
        for (int z = 0; z < n; ++z) {
            for (int x = 0; x < n; ++x) {
                BodyDef d;
                d.shape = Shape::sphere(Real(0.2));
                d.mass = 1;
                d.position = {static_cast<Real>(x), static_cast<Real>(-y), static_cast<Real>(z)};
                d.type = y == 0 ? BodyType::Static : BodyType::Dynamic;
                at(x, y, z) = s.world.createBody(d);
            }
        }
    }
    for (int y = 1; y < n; ++y) {
        for (int z = 0; z < n; ++z) {
            for (int x = 0; x < n; ++x) {
                const BodyId b = at(x, y, z);
                const Vec3 p = s.world.position(b);
                auto link = [&](BodyId a) {
                    JointDef j;
                    j.type = JointType::Ball;
                    j.bodyA = a;
                    j.bodyB = b;
                    j.anchor = (s.world.position(a) + p) * Real(0.5);
                    s.joints.push_back(s.world.createJoint(j));
                };
                link(at(x, y - 1, z));
                if (x > 0) link(at(x - 1, y, z));
                if (z > 0) link(at(x, y, z - 1));
            }
        }
    }
}

struct Result {
    std::string name, description;
    std::size_t bodies = 0, joints = 0, asleep = 0;
    int steps = 0, worstStep = -1;
    double median = 0, mean = 0, worst = 0, end = 0;
    JointType worstType = JointType::Ball;
};

Result run(Scene& s) {
    std::vector<double> ms;
    ms.reserve(static_cast<std::size_t>(s.steps));
    double worst = 0, end = 0;
    int worstStep = -1;
    JointType worstType = JointType::Ball;
    for (int i = 0; i < s.steps; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        s.world.step(Real(1) / 60);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        end = 0;
        for (JointId j : s.joints) {
            const double e = s.world.jointError(j);
            end = std::max(end, e);
            if (e > worst) {
                worst = e;
                worstStep = i;
                worstType = s.world.jointDef(j).type;
            }
        }
    }
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size());
    std::size_t asleep = 0;
    for (BodyId b : s.world.bodies()) asleep += s.world.bodyType(b) == BodyType::Dynamic && !s.world.isAwake(b);
    Result r;
    r.name = s.name;
    r.bodies = s.world.bodyCount();
    r.joints = s.joints.size();
    r.asleep = asleep;
    r.steps = s.steps;
    r.worstStep = worstStep;
    r.median = sorted[sorted.size() / 2];
    r.mean = mean;
    r.worst = worst;
    r.end = end;
    r.worstType = worstType;
    std::printf("%-10s bodies %6zu joints %6zu steps %4d  median %8.3f ms  mean %8.3f ms  worst joint error %.4f m (%s, step %d; end %.4f m)  asleep %zu\n",
                r.name.c_str(), r.bodies, r.joints, r.steps, r.median, r.mean, r.worst, toString(r.worstType), r.worstStep,
                r.end, r.asleep);
    return r;
}

// Three significant figures, as the docs' tables print times.
std::string threeFigures(double ms) {
    char text[32];
    const int decimals = ms >= 100 ? 0 : ms >= 10 ? 1 : ms >= 1 ? 2 : 3;
    std::snprintf(text, sizeof text, "%.*f", decimals, ms);
    return text;
}

void printMarkdown(const std::vector<Result>& results) {
    std::printf("\n| scene | bodies / joints | steps | median ms/step | mean ms/step | worst joint error (end) | asleep at the end |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const Result& r : results)
        std::printf("| %s | %zu / %zu | %d | %s | %s | %.4f m (%.4f m) | %zu |\n", r.description.c_str(), r.bodies, r.joints,
                    r.steps, threeFigures(r.median).c_str(), threeFigures(r.mean).c_str(), r.worst, r.end, r.asleep);
}

}  // namespace

int main(int argc, char** argv) {
    bool quick = false;
    int steps = 0;
    WorldDef def;
    std::string only;
    bool markdown = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        if (std::strcmp(argv[i], "--markdown") == 0) markdown = true;
        if (std::strcmp(argv[i], "--gauss-seidel") == 0) def.jointDirectSolve = false;
        if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) steps = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) def.threads = std::atoi(argv[++i]);
        if (std::strcmp(argv[i], "--scene") == 0 && i + 1 < argc) only = argv[++i];
    }
    const int gridSide = quick ? 10 : 30;
    struct Entry {
        std::string name, description;
        std::function<void(Scene&)> build;
    };
    const std::vector<Entry> scenes = {
        {"chain", "`chain` (bench/scenes.hpp)", buildChain},
        {"ragdolls", "`ragdolls`: 100 ragdolls of 11 bodies (cone-twist + hinges) dropped in a 5 x 5 x 4 pile", buildRagdolls},
        {"grid",
         "`grid`: " + std::to_string(gridSide) + " x " + std::to_string(gridSide) + " x " + std::to_string(gridSide) +
             " spheres, ball joints to the neighbours below and beside, top layer static",
         [&](Scene& s) { buildGrid(s, gridSide); }},
    };
    std::vector<Result> results;
    for (const Entry& entry : scenes) {
        if (!only.empty() && only != entry.name) continue;
        Scene s(entry.name, def);
        entry.build(s);
        s.steps = steps > 0 ? steps : (quick ? 60 : (entry.name == "grid" ? 120 : 600));
        results.push_back(run(s));
        results.back().description = entry.description;
    }
    if (markdown) printMarkdown(results);
}
