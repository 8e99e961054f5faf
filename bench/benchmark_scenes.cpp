// Side-by-side scene benchmark: every scene and accuracy probe of
// docs/benchmarks.md (described once in bench/scenes.hpp) in Fulcrum and in each
// peer engine built in (bench/peers/: Bullet 3, ODE, MuJoCo), in the same run.
// scripts/bench.sh builds and runs it (and --write-docs puts the output in
// docs/benchmarks.md).
//
//   bench_benchmark_scenes [--quick] [--scene PREFIX] [--threads 1,2] [--engines fulcrum,bullet,ode,mujoco]
//                          [--no-probes] [--no-scenes] [--sizes] [--budget SECONDS per engine and scene: 60, --quick 20]
//                          [--rounds N: interleaved rounds per scene, a step's fastest time kept: 3]
//                          [--suite shared|box3d|jolt|churn: docs/benchmarks.md's scenes (default), Box3D's own
//                           benchmark scenes or Jolt's PerformanceTest pyramid (bench/box3d_scenes.hpp), or
//                           both suites' churn and scale scenes (bench/churn_scenes.hpp: rain, washer,
//                           large_world, jolt_high_speed); probes run with the shared suite only]
//
// Per scene, a table: engine, threads, median and mean ms per step, mean over
// the first 120 steps, total seconds, the quality metric and Fulcrum's
// one-thread time divided by the row's, of the medians and of the means (below
// 1: Fulcrum is faster; on Fulcrum's own rows with more threads: the speed-up). Then one table of the
// accuracy probes for every engine, and (--sizes) the bytes per body and per
// contact of Fulcrum's hot data.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <numeric>
#include <optional>
#include <string>

#include "fulcrum/fulcrum.hpp"
#include "peers/peers.hpp"
#include "box3d_scenes.hpp"
#include "churn_scenes.hpp"
#include "fulcrum_world.hpp"
#include "scenes.hpp"
#include "memory_sizes.hpp"

namespace {

using namespace bench;

// ---- Fulcrum as one more Engine ------------------------------------------------
V3 bv(fulcrum::Vec3 v) { return {v.x, v.y, v.z}; }

class FulcrumEngine final : public Engine {
public:
    explicit FulcrumEngine(int threads) : threads_(threads) {}
    std::string name() const override { return "Fulcrum"; }
    int threads() const override { return threads_; }
    std::string settings() const override {
        const fulcrum::WorldDef d;
        char text[400];
        std::snprintf(text, sizeof text,
                      "Fulcrum (float): WorldDef defaults: %d sub-steps, %d iteration, contact %.0f Hz, damping ratio "
                      "%.1f, speculative margin %.2f m, continuous collision on, sleeping on (off for the pyramids and "
                      "probes); cloth: World::createCloth, radius 0.02 m, bend compliance 0.1 m/N (as bench_cloth), "
                      "other ClothDef defaults",
                      d.substeps, d.solverIterations, double(d.contactHertz), double(d.contactDampingRatio),
                      double(d.speculativeMargin));
        return text;
    }

    bool build(const SceneSpec& scene, std::string&) override {
        scene_ = &scene;
        built_ = buildFulcrumWorld(scene, threads_);
        pushOutFromEnvironment(*built_.world);
        world_ = built_.world.get();
        ids_ = built_.bodies;
        cloth_ = built_.cloth;
        script_ = std::make_unique<FulcrumScript>(scene, built_);
        return true;
    }
    void createGroup(int group) override { script_->create(group); }
    void destroyGroup(int group) override { script_->destroy(group); }
    std::vector<V3> dynamicPositions() const override {
        std::vector<V3> out;
        for (std::size_t i = 0; i < ids_.size(); ++i) {
            if (!scene_->bodies[i].isStatic && !scene_->bodies[i].isKinematic) out.push_back(bv(world_->position(ids_[i])));
        }
        for (const fulcrum::BodyId id : script_->liveBodies()) out.push_back(bv(world_->position(id)));
        return out;
    }
    void step() override { world_->step(static_cast<fulcrum::Real>(scene_->dt)); }
    void moveKinematic(std::size_t i, V3 origin, double dt) override {
        world_->moveKinematic(ids_[i], fulcrum::Transform{toFulcrum(origin), fulcrum::Quat{}}, static_cast<fulcrum::Real>(dt));
    }
    BodyState body(std::size_t i) const override {
        const fulcrum::BodyId id = ids_[i];
        const fulcrum::Quat q = world_->orientation(id);
        return {bv(world_->position(id)), {q.w, q.x, q.y, q.z}, bv(world_->linearVelocity(id)), bv(world_->angularVelocity(id))};
    }
    bool asleep(std::size_t i) const override { return !world_->isAwake(ids_[i]); }
    double deepestPenetration() const override {
        double deepest = 0;
        for (const fulcrum::ContactReport& c : world_->contacts()) deepest = std::max(deepest, double(c.depth));
        return deepest;
    }
    std::vector<V3> clothParticles() const override {
        std::vector<V3> out;
        if (cloth_.isNull()) return out;
        for (const fulcrum::Vec3& p : world_->particlePositions(cloth_)) out.push_back(bv(p));
        return out;
    }

private:
    int threads_;
    const SceneSpec* scene_ = nullptr;
    FulcrumWorld built_;
    std::unique_ptr<FulcrumScript> script_;
    fulcrum::World* world_ = nullptr;
    std::vector<fulcrum::BodyId> ids_;
    fulcrum::ParticleSystemId cloth_;
};

// ---- measuring -------------------------------------------------------------------
struct Result {
    std::string engine;
    int threads = 1;
    bool ran = false;
    std::string why;              // when not ran
    std::vector<double> stepMs;   // per step: the fastest of the rounds (mergeRound)
    int rounds = 1;
    bool stopped = false;         // the budget ran out
    std::string quality;
    double probe = 0;             // the probe's measured value
    double probe2 = 0;            // spin: |L| drift
};

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

std::string format(const char* fmt, auto... args) {
    char text[512];
    std::snprintf(text, sizeof text, fmt, args...);
    return text;
}

// Box inertia about its centre, body axes (diagonal).
V3 boxInertia(const BodySpec& b) {
    const double x2 = b.half.x * b.half.x, y2 = b.half.y * b.half.y, z2 = b.half.z * b.half.z;
    return {b.mass * (y2 + z2) / 3, b.mass * (x2 + z2) / 3, b.mass * (x2 + y2) / 3};
}
// Kinetic energy and angular momentum magnitude of a free box.
std::pair<double, double> spinEnergyMomentum(const BodySpec& spec, const BodyState& s) {
    const V3 inertia = boxInertia(spec);
    const V3 wl = rotate(conjugate(s.orientation), s.angularVelocity);
    const V3 ll{inertia.x * wl.x, inertia.y * wl.y, inertia.z * wl.z};
    return {0.5 * dot(wl, ll), length(ll)};
}

// The mesh scenes (bench/mesh_scenes.hpp): how many dynamic bodies ended with
// their origin more than kThrough below the mesh surface under it (fell
// through it: a resting body's origin, at most on its own surface, is above
// the mesh or a hair below it, as a pyramid's on its base), the lowest origin
// relative to the surface, and how many left the mesh's extent.
std::string meshQuality(const Engine& engine, const SceneSpec& scene) {
    constexpr double kThrough = 0.1;
    V3 meshOrigin;
    int mesh = -1;
    for (const BodySpec& b : scene.bodies) {
        if (b.mesh >= 0) {
            mesh = b.mesh;
            meshOrigin = b.position;
        }
    }
    int below = 0, off = 0;
    double lowest = 1e30;
    const MeshColumns columns(*scene.meshes[static_cast<std::size_t>(mesh)], meshOrigin);
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
        if (scene.bodies[i].isStatic || scene.bodies[i].isKinematic) continue;
        const V3 p = engine.body(i).position;
        const std::optional<double> surface = columns.surfaceHeight(p);
        if (!surface) {
            ++off;
            continue;
        }
        lowest = std::min(lowest, p.y - *surface);
        if (p.y < *surface - kThrough) ++below;
    }
    return format("; **fell through the mesh %d** (origin > %.1f m under it), lowest origin %+.3f m from the surface, off the mesh %d",
                  below, kThrough, lowest, off);
}

// Seconds one engine may spend stepping one scene; a slower engine stops there
// and its row says after how many steps (the harness must finish in minutes).
double gBudgetSeconds = 60;

Result run(Engine& engine, const SceneSpec& scene) {
    Result r;
    r.engine = engine.name();
    r.threads = engine.threads();
    if (!engine.build(scene, r.why)) return r;
    r.ran = true;
    engine.sync();
    const std::size_t n = scene.bodies.size();
    std::vector<BodyState> start(n);
    for (std::size_t i = 0; i < n; ++i) start[i] = engine.body(i);
    // Joint anchors in each body's frame at the start (the world anchor for the world side).
    struct LocalAnchors {
        V3 a, b;
    };
    std::vector<LocalAnchors> anchors;
    for (const JointSpec& j : scene.joints) {
        LocalAnchors la;
        la.a = j.a < 0 ? j.anchor : rotate(conjugate(start[std::size_t(j.a)].orientation), j.anchor - start[std::size_t(j.a)].position);
        la.b = rotate(conjugate(start[std::size_t(j.b)].orientation), j.anchor - start[std::size_t(j.b)].position);
        anchors.push_back(la);
    }
    auto anchorWorld = [&](int body, V3 local) {
        if (body < 0) return local;
        const BodyState s = engine.body(static_cast<std::size_t>(body));
        return s.position + rotate(s.orientation, local);
    };
    auto worstJointError = [&] {
        double worst = 0;
        for (std::size_t k = 0; k < scene.joints.size(); ++k) {
            const JointSpec& j = scene.joints[k];
            worst = std::max(worst, length(anchorWorld(j.a, anchors[k].a) - anchorWorld(j.b, anchors[k].b)));
        }
        return worst;
    };

    double jointErrorMax = 0;
    std::vector<double> upCrossings;  // pendulum: times x crosses 0 going up
    double previousX = start.empty() ? 0 : start[0].position.x;
    r.stepMs.reserve(static_cast<std::size_t>(scene.steps));
    double elapsedMs = 0;
    int stoppedAt = -1;
    std::size_t nextEvent = 0;
    for (int i = 0; i < scene.steps; ++i) {
        if (elapsedMs > 1000 * gBudgetSeconds) {
            stoppedAt = i;
            break;
        }
        for (const KinematicPath& path : scene.kinematicPaths) {
            engine.moveKinematic(static_cast<std::size_t>(path.body), path.origin(i), scene.dt);
        }
        const auto t0 = std::chrono::steady_clock::now();
        // A churn scene's script runs with the step it comes before, timed as Box3D's benchmark times it.
        while (nextEvent < scene.script.size() && scene.script[nextEvent].step <= i) {
            const ScriptEvent& e = scene.script[nextEvent++];
            if (e.create) {
                engine.createGroup(e.group);
            } else {
                engine.destroyGroup(e.group);
            }
        }
        engine.step();
        const auto t1 = std::chrono::steady_clock::now();
        r.stepMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        elapsedMs += r.stepMs.back();
        if (scene.kind == SceneSpec::Kind::Chain || scene.kind == SceneSpec::Kind::Jointed) {
            engine.sync();
            jointErrorMax = std::max(jointErrorMax, worstJointError());
        } else if (scene.probe == Probe::Pendulum) {
            engine.sync();
            const double x = engine.body(0).position.x;
            if (previousX < 0 && x >= 0) upCrossings.push_back((i + (-previousX) / (x - previousX)) * scene.dt);
            previousX = x;
        }
    }
    engine.sync();

    switch (scene.kind) {
        case SceneSpec::Kind::Bodies: {
            double drift = 0;
            int asleep = 0;
            for (std::size_t i = 0; i < n; ++i) {
                if (scene.bodies[i].isStatic) continue;
                const V3 d = engine.body(i).position - start[i].position;
                drift = std::max(drift, std::sqrt(d.x * d.x + d.z * d.z));
                if (engine.asleep(i)) ++asleep;
            }
            if (scene.pyramid) {
                const auto top = static_cast<std::size_t>(scene.topIndex);
                const double sink = start[top].position.y - engine.body(top).position.y;
                const bool stands = drift < 0.05 && sink < 0.25;
                r.quality = format("%s: drift %.3f m, sink %.3f m; ", stands ? "stands" : "FAILS", drift, sink);
            }
            r.quality += format("asleep %d, deepest %.4f m", asleep, engine.deepestPenetration());
            if (!scene.meshes.empty()) r.quality += meshQuality(engine, scene);
            if (scene.fixedCost) r.quality = format("**%.1f us/step** (median); ", 1000 * median(r.stepMs)) + r.quality;
            break;
        }
        case SceneSpec::Kind::Chain: {
            const JointSpec& last = scene.joints.back();
            const BodyState s = engine.body(static_cast<std::size_t>(last.b));
            const V3 anchor = s.position + rotate(s.orientation, anchors.back().b);
            const V3 freeEnd = s.position * 2 - anchor;
            r.quality = format("joint error max %.3f m, end %.4f m; free end y %.2f m", jointErrorMax, worstJointError(), freeEnd.y);
            break;
        }
        case SceneSpec::Kind::Jointed:
            r.quality = format("joint error max %.4f m, end %.4f m", jointErrorMax, worstJointError());
            break;
        case SceneSpec::Kind::Churn: {
            // What a churn or scale scene can get wrong: bodies through a floor or
            // out of their container (the mesh, the drum, continuous collision),
            // bodies resting where they should not, overlaps.
            const std::vector<V3> live = engine.dynamicPositions();
            int escaped = 0;
            double lowest = 1e30;
            for (const V3& p : live) {
                const bool inside = p.x >= scene.boundsMin.x && p.x <= scene.boundsMax.x && p.y >= scene.boundsMin.y &&
                                    p.y <= scene.boundsMax.y && p.z >= scene.boundsMin.z && p.z <= scene.boundsMax.z;
                if (!inside) ++escaped;
                lowest = std::min(lowest, p.y);
            }
            r.quality = format("%zu dynamic bodies, **%d escaped**", live.size(), escaped);
            if (scene.restHeight > -1e29) r.quality += format(", lowest %.4f m (rests at %.2f m)", lowest, scene.restHeight);
            int asleep = 0;
            for (std::size_t i = 0; i < n; ++i) {
                if (!scene.bodies[i].isStatic && !scene.bodies[i].isKinematic && engine.asleep(i)) ++asleep;
            }
            r.quality += format(", deepest %.4f m", engine.deepestPenetration());
            if (asleep > 0) r.quality += format(", asleep %d", asleep);
            break;
        }
        case SceneSpec::Kind::Cloth: {
            const std::vector<V3> p = engine.clothParticles();
            const int cn = scene.cloth.n;
            double sum = 0, worst = 0, deepest = 0;
            int count = 0;
            for (int j = 0; j < cn; ++j) {
                for (int i = 0; i < cn; ++i) {
                    const V3 a = p[std::size_t(j * cn + i)];
                    deepest = std::max(deepest, scene.cloth.sphereRadius - length(a - scene.cloth.sphereCenter));
                    for (const int o : {1, cn}) {
                        if ((o == 1 && i + 1 >= cn) || (o == cn && j + 1 >= cn)) continue;
                        const double s = (length(p[std::size_t(j * cn + i + o)] - a) - scene.cloth.spacing) / scene.cloth.spacing;
                        sum += s;
                        worst = std::max(worst, s);
                        ++count;
                    }
                }
            }
            r.quality = format("stretch mean %.4f, max %.4f; deepest particle centre in sphere %.4f m", sum / count, worst, deepest);
            break;
        }
        case SceneSpec::Kind::Probe: {
            const BodySpec& spec = scene.bodies.back();
            const BodyState s = engine.body(scene.bodies.size() - 1);
            switch (scene.probe) {
                case Probe::FreeFall: r.probe = s.position.y - spec.position.y; break;
                case Probe::Pendulum:
                    // Over (up to) 10 oscillations; probe2 = how many.
                    if (upCrossings.size() >= 2) {
                        const std::size_t last = std::min<std::size_t>(10, upCrossings.size() - 1);
                        r.probe = (upCrossings[last] - upCrossings[0]) / static_cast<double>(last);
                        r.probe2 = static_cast<double>(last);
                    } else {
                        r.probe = -1;
                    }
                    break;
                case Probe::Slope20:
                case Probe::Slope30: r.probe = length(s.position - spec.position); break;
                case Probe::Spin: {
                    BodyState s0;
                    s0.orientation = spec.orientation;
                    s0.angularVelocity = spec.angularVelocity;
                    const auto [e0, l0] = spinEnergyMomentum(spec, s0);
                    const auto [e1, l1] = spinEnergyMomentum(spec, s);
                    r.probe = (e1 - e0) / e0;
                    r.probe2 = (l1 - l0) / l0;
                    break;
                }
                case Probe::None: break;
            }
            break;
        }
    }
    const std::string note = engine.note();
    if (!note.empty()) r.quality += "; " + note;
    if (stoppedAt >= 0) {
        r.stopped = true;
        r.quality = format("**stopped after %d of %d steps** (%.0f s budget), at that point: ", stoppedAt, scene.steps,
                           gBudgetSeconds) + r.quality;
    }
    return r;
}

using Factory = std::function<std::unique_ptr<Engine>()>;

struct Options {
    bool quick = false, probes = true, scenes = true, sizes = false;
    std::string only;
    std::vector<int> threads{1, 2};
    std::string engines = "fulcrum,bullet,ode,mujoco";
    std::string suite = "shared";  // shared: docs/benchmarks.md's scenes; box3d: Box3D's own (bench/box3d_scenes.hpp)
    int rounds = 3;
};

// Rounds. Every engine steps every scene in `rounds` interleaved rounds
// (Fulcrum 1 thread, Fulcrum 2 threads, Bullet, ODE, MuJoCo, then again), and a
// step's time is the fastest it took over the rounds: each engine is
// deterministic, so a step does the same work every round, and on this shared
// VM noise only ever adds time (one build's box_pile 2-thread speed-up
// measured 0.93x and 1.94x in two single-round runs). Every engine gets the
// same rounds, so the ratios stay like for like; only a run stopped at the
// budget is not repeated.
bool worthRepeating(const Result& r) {
    return r.ran && !r.stopped;
}

// The fastest time of each step over the rounds; the quality is the first
// round's (the same, every engine being deterministic).
void mergeRound(Result& best, const Result& again) {
    const std::size_t n = std::min(best.stepMs.size(), again.stepMs.size());
    for (std::size_t i = 0; i < n; ++i) best.stepMs[i] = std::min(best.stepMs[i], again.stepMs[i]);
    ++best.rounds;
}

std::vector<Factory> engines(const Options& o) {
    std::vector<Factory> out;
    auto wanted = [&](const char* name) { return o.engines.find(name) != std::string::npos; };
    if (wanted("fulcrum")) {
        for (int t : o.threads) out.push_back([t] { return std::make_unique<FulcrumEngine>(t); });
    }
#ifdef FULCRUM_HAVE_BULLET
    if (wanted("bullet")) out.push_back(makeBullet);
#endif
#ifdef FULCRUM_HAVE_ODE
    if (wanted("ode")) out.push_back(makeOde);
#endif
#ifdef FULCRUM_HAVE_MUJOCO
    if (wanted("mujoco")) out.push_back(makeMujoco);
#endif
    return out;
}

void printScene(const SceneSpec& scene, const std::vector<Result>& results) {
    std::printf("\n### %s (%d steps)\n\n", scene.name.c_str(), scene.steps);
    std::string rounds;
    for (const Result& r : results) {
        if (!r.ran) continue;
        rounds += format("%s%s %dt %d", rounds.empty() ? "" : ", ", r.engine.c_str(), r.threads, r.rounds);
    }
    if (!rounds.empty()) std::printf("Rounds (a step's time: its fastest): %s.\n\n", rounds.c_str());
    std::printf("| engine | threads | median ms | mean ms | first 120 ms | total s | quality | Fulcrum 1t / this: medians (means) |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    double reference = 0, referenceMedian = 0;
    for (const Result& r : results) {
        if (r.ran && r.engine == "Fulcrum" && r.threads == 1) {
            reference = mean(r.stepMs, r.stepMs.size());
            referenceMedian = median(r.stepMs);
        }
    }
    for (const Result& r : results) {
        if (!r.ran) {
            std::printf("| %s | %d | - | - | - | - | not run: %s | - |\n", r.engine.c_str(), r.threads, r.why.c_str());
            continue;
        }
        const double m = mean(r.stepMs, r.stepMs.size());
        const double total = std::accumulate(r.stepMs.begin(), r.stepMs.end(), 0.0) / 1000;
        std::printf("| %s | %d | %.3f | %.3f | %.3f | %.2f | %s | ", r.engine.c_str(), r.threads, median(r.stepMs), m,
                    mean(r.stepMs, 120), total, r.quality.c_str());
        if (reference > 0 && m > 0) {
            std::printf("%.3g (%.3g) |\n", referenceMedian / median(r.stepMs), reference / m);
        } else {
            std::printf("- |\n");
        }
    }
    std::fflush(stdout);
}

void printProbes(const std::vector<SceneSpec>& probes, const std::vector<std::vector<Result>>& results) {
    std::printf("\n### Accuracy probes (one thread)\n\n| probe | expected |");
    for (const Result& r : results.front()) std::printf(" %s |", r.engine.c_str());
    std::printf("\n|---|---|");
    for (std::size_t i = 0; i < results.front().size(); ++i) std::printf("---|");
    std::printf("\n");
    for (std::size_t p = 0; p < probes.size(); ++p) {
        const SceneSpec& s = probes[p];
        const char* expected = "";
        switch (s.probe) {
            case Probe::FreeFall: expected = "drop -4.905 m"; break;
            case Probe::Pendulum: expected = "period 2.014 s (2.010 s x 1.002 for the bob's inertia)"; break;
            case Probe::Slope20: expected = "stays: 0 m"; break;
            case Probe::Slope30: expected = "slides 1.314 m (g (sin 30 - 0.5 cos 30) t^2 / 2)"; break;
            case Probe::Spin: expected = "KE and \\|L\\| drift 0"; break;
            case Probe::None: break;
        }
        std::printf("| %s | %s |", s.name.c_str(), expected);
        for (const Result& r : results[p]) {
            if (!r.ran) {
                std::printf(" not run |");
            } else if (s.probe == Probe::Spin) {
                std::printf(" KE %+.2e, \\|L\\| %+.2e |", r.probe, r.probe2);
            } else if (s.probe == Probe::FreeFall) {
                std::printf(" %.4f m (%+.2f %%) |", r.probe, 100 * (r.probe / -4.905 - 1));
            } else if (s.probe == Probe::Pendulum) {
                if (r.probe < 0) {
                    std::printf(" no full period |");
                } else {
                    std::printf(" %.4f s (%+.2f %%)%s |", r.probe, 100 * (r.probe / 2.014 - 1),
                                r.probe2 < 10 ? format(" over %.0f periods", r.probe2).c_str() : "");
                }
            } else {
                std::printf(" %.4f m |", r.probe);
            }
        }
        std::printf("\n");
    }
    std::fflush(stdout);
}

std::vector<int> parseThreads(const char* text) {
    std::vector<int> out;
    for (const char* p = text; *p != 0;) {
        out.push_back(std::max(1, std::atoi(p)));
        const char* comma = std::strchr(p, ',');
        if (comma == nullptr) break;
        p = comma + 1;
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    bool budgetGiven = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) o.quick = true;
        else if (std::strcmp(argv[i], "--no-probes") == 0) o.probes = false;
        else if (std::strcmp(argv[i], "--no-scenes") == 0) o.scenes = false;
        else if (std::strcmp(argv[i], "--sizes") == 0) o.sizes = true;
        else if (std::strcmp(argv[i], "--fulcrum-only") == 0) o.engines = "fulcrum";
        else if (std::strcmp(argv[i], "--scene") == 0 && i + 1 < argc) o.only = argv[++i];
        else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) o.threads = parseThreads(argv[++i]);
        else if (std::strcmp(argv[i], "--engines") == 0 && i + 1 < argc) o.engines = argv[++i];
        else if (std::strcmp(argv[i], "--suite") == 0 && i + 1 < argc) o.suite = argv[++i];
        else if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) o.rounds = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--budget") == 0 && i + 1 < argc) {
            gBudgetSeconds = std::atof(argv[++i]);
            budgetGiven = true;
        }
        else {
            std::fprintf(stderr,
                         "usage: %s [--quick] [--scene PREFIX] [--threads 1,2] [--engines fulcrum,bullet,ode,mujoco] "
                         "[--fulcrum-only] [--suite shared|box3d|jolt|churn] [--no-probes] [--no-scenes] [--sizes] [--budget SECONDS] [--rounds N]\n",
                         argv[0]);
            return 2;
        }
    }
    if (o.quick && !budgetGiven) gBudgetSeconds = 20;
    const std::vector<Factory> factories = engines(o);
    std::printf("### Engines and their settings\n\n");
    for (const Factory& f : factories) {
        const auto e = f();
        if (e->name() == "Fulcrum" && e->threads() != o.threads.front()) continue;
        std::printf("- %s\n", e->settings().c_str());
    }
    if (o.sizes) printMemorySizes();
    if (o.scenes) {
        const std::vector<LazyScene> suite = o.suite == "box3d"   ? box3dScenes(o.quick)
                                             : o.suite == "jolt"  ? joltScenes(o.quick)
                                             : o.suite == "churn" ? churnScenes(o.quick)
                                                                  : allScenes(o.quick);
        for (const LazyScene& lazy : suite) {
            if (!o.only.empty() && lazy.name.rfind(o.only, 0) != 0) continue;
            const SceneSpec scene = lazy.build();
            std::vector<Result> results;
            for (const Factory& f : factories) {
                const auto e = f();
                results.push_back(run(*e, scene));
            }
            for (int round = 1; round < o.rounds; ++round) {
                for (std::size_t k = 0; k < factories.size(); ++k) {
                    if (!worthRepeating(results[k])) continue;
                    const auto e = factories[k]();
                    mergeRound(results[k], run(*e, scene));
                }
            }
            printScene(scene, results);
        }
    }
    if (o.probes && o.only.empty() && o.suite == "shared") {
        const std::vector<SceneSpec> probes = allProbes();
        std::vector<std::vector<Result>> results;
        for (const SceneSpec& probe : probes) {
            std::vector<Result> row;
            for (const Factory& f : factories) {
                const auto e = f();
                if (e->threads() != 1) continue;
                row.push_back(run(*e, probe));
            }
            results.push_back(std::move(row));
        }
        printProbes(probes, results);
    }
    return 0;
}
