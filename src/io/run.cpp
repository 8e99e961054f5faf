// `fulcrum run` as a library: overrides, the run loop and its outputs.
#include "io/run.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <limits>
#include <cmath>
#include <cstdio>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <optional>
#include <ostream>
#include <span>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fulcrum/snapshot.hpp"
#include "fulcrum/recording.hpp"
#include "io/scene_detail.hpp"
#include "math/real_bits.hpp"
#include "io/svg_plot.hpp"

namespace fulcrum::detail {

namespace {

using ojson = nlohmann::ordered_json;

// A value's JSON text. Body names and the source's name are bytes from the
// C++ API, a snapshot or a file path and need not be UTF-8: such bytes are
// written as U+FFFD instead of failing the whole report.
std::string jsonText(const ojson& j) { return j.dump(-1, ' ', false, ojson::error_handler_t::replace); }

double num(Real v) { return std::strtod(formatNumber(v).c_str(), nullptr); }
ojson vec(const Vec3& v) { return ojson::array({num(v.x), num(v.y), num(v.z)}); }
ojson quat(const Quat& q) { return ojson::array({num(q.w), num(q.x), num(q.y), num(q.z)}); }

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// A progress bar on stderr, redrawn at most 100 times per run.
class ProgressBar {
public:
    ProgressBar(bool enabled, int total) : enabled_(enabled && total > 0), total_(total) {}
    ~ProgressBar() {
        if (enabled_ && drawn_) std::fprintf(stderr, "\r%60s\r", "");
    }
    void update(int step) {
        if (!enabled_) return;
        const int percent = static_cast<int>(100LL * step / total_);
        if (percent == last_) return;
        last_ = percent;
        drawn_ = true;
        constexpr int kWidth = 30;
        char bar[kWidth + 1];
        const int filled = percent * kWidth / 100;
        for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
        bar[kWidth] = '\0';
        std::fprintf(stderr, "\r[%s] %3d%% step %d/%d", bar, percent, step, total_);
        std::fflush(stderr);
    }

private:
    bool enabled_;
    int total_;
    int last_ = -1;
    bool drawn_ = false;
};

void writeCsvRows(std::FILE* f, const World& world, const Scene& scene, const SceneHandles& handles, std::uint64_t step) {
    const std::string t = formatNumber(world.time());  // shortest text of the float: 0.0166667, not 0.0166666992
    for (std::size_t i = 0; i < handles.bodies.size(); ++i) {
        if (scene.bodies[i].def.type != BodyType::Dynamic) continue;
        const BodyId id = handles.bodies[i];
        const Vec3 p = world.position(id), v = world.linearVelocity(id), w = world.angularVelocity(id);
        const Quat q = world.orientation(id);
        std::fprintf(f, "%llu,%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                     static_cast<unsigned long long>(step), t.c_str(), sceneBodyName(scene, i).c_str(), double(p.x), double(p.y),
                     double(p.z), double(q.w), double(q.x), double(q.y), double(q.z), double(v.x), double(v.y), double(v.z),
                     double(w.x), double(w.y), double(w.z));
    }
}

// Display name of particle system k of the scene's ropes (or cloths): its
// name, or "rope<k>" / "cloth<k>" when unnamed.
std::string particleSystemName(const Scene& scene, bool cloth, std::size_t k) {
    const std::string& name = cloth ? scene.cloths[k].def.name : scene.ropes[k].def.name;
    return name.empty() ? (cloth ? "cloth" : "rope") + std::to_string(k) : name;
}

// --csv-particles: one row per particle in the body row format, named
// "r1[3]" (particle 3 of r1; cloth particle (i, j) is j * nu + i), with the
// identity orientation and zero angular velocity.
void writeCsvParticleRows(std::FILE* f, const World& world, const Scene& scene, const SceneHandles& handles,
                          std::uint64_t step) {
    const std::string t = formatNumber(world.time());
    for (int kind = 0; kind < 2; ++kind) {
        const std::vector<ParticleSystemId>& ids = kind == 0 ? handles.ropes : handles.cloths;
        for (std::size_t k = 0; k < ids.size(); ++k) {
            const std::string name = particleSystemName(scene, kind == 1, k);
            const std::span<const Vec3> x = world.particlePositions(ids[k]);
            for (std::size_t i = 0; i < x.size(); ++i) {
                const Vec3 v = world.particleVelocity(ids[k], i);
                std::fprintf(f, "%llu,%s,%s[%zu],%.9g,%.9g,%.9g,1,0,0,0,%.9g,%.9g,%.9g,0,0,0\n",
                             static_cast<unsigned long long>(step), t.c_str(), name.c_str(), i, double(x[i].x),
                             double(x[i].y), double(x[i].z), double(v.x), double(v.y), double(v.z));
            }
        }
    }
}

RunSample sample(const World& world) {
    return {static_cast<double>(world.time()), world.energy(), static_cast<double>(length(world.linearMomentum())),
            static_cast<double>(length(world.angularMomentum()))};
}

// The reported energy and momenta are sums over the bodies, and a finite
// state can still overflow them: a body at x = 3e38 m that moves at all has an
// angular momentum about the origin beyond float range. The run stops as for a
// NaN state (exit 3), naming the body with the largest term of the sum that
// overflowed, instead of reporting null.
void checkReportFinite(const World& world, const Scene& scene, const SceneHandles& handles, std::uint64_t step) {
    const bool linear = isFinite(world.linearMomentum()), angular = isFinite(world.angularMomentum());
    const bool energy = std::isfinite(world.energy().total);
    if (linear && angular && energy) return;
    const char* quantity = !linear ? "linear momentum" : !angular ? "angular momentum about the origin" : "energy";
    std::size_t culprit = 0;
    double largest = -1;
    for (std::size_t i = 0; i < handles.bodies.size(); ++i) {
        if (scene.bodies[i].def.type != BodyType::Dynamic) continue;
        const BodyId id = handles.bodies[i];
        const Vec3 c = world.centerOfMass(id), lv = world.linearVelocity(id), av = world.angularVelocity(id);
        const double m = world.mass(id), r = std::hypot(double(c.x), double(c.y), double(c.z));
        const double v = std::hypot(double(lv.x), double(lv.y), double(lv.z)), w = std::hypot(double(av.x), double(av.y), double(av.z));
        const double term = !linear ? m * v : !angular ? m * (v * r + w) : m * (v * v + w * w + r);
        if (!(term <= largest)) {  // NaN and infinity win
            largest = term;
            culprit = i;
        }
    }
    std::string who = "the ropes and cloths";
    if (largest >= 0) {
        const Vec3 c = world.centerOfMass(handles.bodies[culprit]);
        const double distance = std::hypot(double(c.x), double(c.y), double(c.z));  // in double: its float square may overflow
        char far[32];
        std::snprintf(far, sizeof far, "%.3g", distance);
        who = "body '" + sceneBodyName(scene, culprit) + "' (index " + std::to_string(culprit) + ", " + far + " m from the origin)";
    }
    throw NumericalError(who + ": the " + quantity + " became NaN/inf (beyond float range) at step " + std::to_string(step) +
                         " (t = " + formatNumber(world.time()) + " s)");
}

std::string plotSvg(const Scene& scene, const std::vector<RunSample>& samples) {
    std::vector<double> t, ke, pe, te, p, l;
    for (const RunSample& s : samples) {
        t.push_back(s.time);
        ke.push_back(s.energy.kinetic);
        pe.push_back(s.energy.potential);
        te.push_back(s.energy.total);
        p.push_back(s.linearMomentum);
        l.push_back(s.angularMomentum);
    }
    std::vector<PlotPanel> panels;
    panels.push_back({"Energy", "energy (J)",
                      {{"kinetic", ke, "#1f77b4"}, {"potential", pe, "#ff7f0e"}, {"total", te, "#2ca02c"}}});
    panels.push_back({"Linear momentum", "|p| (kg m/s)", {{"|p|", p, "#d62728"}}});
    panels.push_back({"Angular momentum about the origin", "|L| (kg m\u00b2/s)", {{"|L|", l, "#9467bd"}}});
    const std::string name = scene.sourceName.empty() ? "fulcrum run" : scene.sourceName;
    return svgPlot(name + ": energy and momentum", "time (s)", t, panels);
}

std::string jointName(const Scene& scene, std::size_t i) {
    return scene.joints[i].def.name.empty() ? "joint" + std::to_string(i) : scene.joints[i].def.name;
}

}  // namespace

namespace {

// The whole-number options and their ranges, in one place for the parsing of
// their text (parseIntegerOption) and the check of their values (applyOverrides).
struct IntegerOption {
    std::string_view name;
    long long lo, hi;
};
constexpr IntegerOption kIntegerOptions[] = {
    {"--steps", 0, std::numeric_limits<int>::max()},
    {"--substeps", 1, kSceneMaxSubsteps},
    {"--threads", 1, kMaxThreads},
};

const IntegerOption& integerOption(std::string_view name) {
    for (const IntegerOption& o : kIntegerOptions) {
        if (o.name == name) return o;
    }
    throw OptionError(std::string(name) + ": not a whole-number option");
}

[[noreturn]] void integerOutOfRange(const IntegerOption& o, const std::string& got) {
    throw OptionError(std::string(o.name) + ": must be between " + std::to_string(o.lo) + " and " + std::to_string(o.hi) + ", got " + got);
}

int checkedInteger(std::string_view name, long long value) {
    const IntegerOption& o = integerOption(name);
    if (value < o.lo || value > o.hi) integerOutOfRange(o, std::to_string(value));
    return static_cast<int>(value);
}

}  // namespace

long long parseIntegerOption(std::string_view name, const std::string& text) {
    const IntegerOption& o = integerOption(name);
    long long value = 0;
    const char* end = text.data() + text.size();
    const auto [at, ec] = std::from_chars(text.data(), end, value);
    // Too large even for a long long: still the range, with the text as written.
    if (ec == std::errc::result_out_of_range && at == end) integerOutOfRange(o, text);
    if (ec != std::errc() || at != end || text.empty()) {
        throw OptionError(std::string(name) + ": must be a whole number between " + std::to_string(o.lo) + " and " + std::to_string(o.hi) +
                          ", got '" + text + "'");
    }
    checkedInteger(name, value);
    return value;
}

void applyOverrides(Scene& scene, const RunOverrides& o) {
    if (o.steps) scene.steps = checkedInteger("--steps", *o.steps);
    if (o.dt) {
        if (!std::isfinite(*o.dt) || !(*o.dt > 0) || *o.dt > 1e6) {
            throw OptionError("--dt: must be a positive time step in seconds, at most 1e6, got " + formatNumber(*o.dt));
        }
        if (static_cast<Real>(*o.dt) < std::numeric_limits<Real>::min()) {
            // It would round to 0 or a denormal in the engine's floats; say so here
            // rather than let the world blame the scene file for it.
            throw OptionError(std::string("--dt: too small for the engine's ") + fulcrum::detail::kRealPrecision + " numbers (at least " +
                              formatNumber(std::numeric_limits<Real>::min()) + " s), got " + formatNumber(*o.dt));
        }
        scene.dt = static_cast<Real>(*o.dt);
    }
    if (o.substeps) scene.world.substeps = checkedInteger("--substeps", *o.substeps);
    if (o.integrator) {
        const auto integrator = integratorFromString(*o.integrator);
        if (!integrator) throw OptionError("--integrator: unknown integrator '" + *o.integrator + "' (valid: " + integratorList() + ")");
        scene.world.integrator = *integrator;
    }
    if (o.threads) scene.world.threads = checkedInteger("--threads", *o.threads);
    if (o.pushOutGrownOverlaps) scene.world.pushOutGrownOverlaps = *o.pushOutGrownOverlaps;
}

RunResult runScene(const Scene& scene, const RunOutputs& outputs, const StepObserver& observer) {
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    return runWorld(std::move(world), handles, scene, outputs, observer);
}

namespace {
// What `fulcrum run` keeps in a snapshot's user data to resume a run: the
// step, the scene's total steps and its name.
std::string runRecord(const Scene& scene) {
    ojson j{{"fulcrum_run", 1}, {"dt", static_cast<double>(scene.dt)}, {"steps", scene.steps}, {"source", scene.sourceName}};
    return jsonText(j);
}
}  // namespace

Scene resumeScene(const World& world, const std::string& userData, const std::string& source, SceneHandles& handles) {
    Scene scene;
    scene.sourceName = source;
    scene.world = world.settings();
    scene.dt = 0;
    scene.steps = 0;
    const ojson record = ojson::parse(userData, nullptr, false);
    if (record.is_object() && record.contains("fulcrum_run")) {
        if (record.contains("dt") && record["dt"].is_number()) scene.dt = static_cast<Real>(record["dt"].get<double>());
        if (record.contains("steps") && record["steps"].is_number_integer()) {
            const long long total = record["steps"].get<long long>();
            const long long done = static_cast<long long>(world.stepCount());
            scene.steps = static_cast<int>(std::clamp<long long>(total - done, 0, std::numeric_limits<int>::max()));
        }
        if (record.contains("source") && record["source"].is_string() && !record["source"].get<std::string>().empty()) {
            scene.sourceName = record["source"].get<std::string>() + " (resumed from " + source + ")";
        }
    }
    handles = {};
    for (const BodyId id : world.bodies()) {
        SceneBody b;
        b.def.name = world.name(id);
        b.def.type = world.bodyType(id);
        scene.bodies.push_back(std::move(b));
        handles.bodies.push_back(id);
    }
    for (const JointId id : world.joints()) {
        SceneJoint j;
        j.def = world.jointDef(id);
        scene.joints.push_back(std::move(j));
        handles.joints.push_back(id);
    }
    for (const ParticleSystemId id : world.particleSystems()) {
        if (world.particleSystemType(id) == ParticleSystemType::Rope) {
            SceneRope rope;
            rope.def.name = world.name(id);
            scene.ropes.push_back(std::move(rope));
            handles.ropes.push_back(id);
        } else {
            SceneCloth cloth;
            cloth.def.name = world.name(id);
            scene.cloths.push_back(std::move(cloth));
            handles.cloths.push_back(id);
        }
    }
    return scene;
}

RunResult runWorld(World built, const SceneHandles& handles, const Scene& scene, const RunOutputs& outputs,
                   const StepObserver& observer) {
    if (outputs.snapshotAt.has_value() != !outputs.snapshotPath.empty()) {
        throw OptionError(outputs.snapshotAt ? "--snapshot-at: needs --snapshot FILE to write the state to"
                                             : "--snapshot " + outputs.snapshotPath + ": needs --snapshot-at N (the step after which to save)");
    }
    if (outputs.snapshotAt) {
        const long long first = static_cast<long long>(built.stepCount());
        const long long last = first + scene.steps;
        if (*outputs.snapshotAt < first || *outputs.snapshotAt > last) {
            throw OptionError("--snapshot-at: must be a step of this run, " + std::to_string(first) + " to " +
                              std::to_string(last) + ", got " + std::to_string(*outputs.snapshotAt));
        }
        std::ofstream probe(outputs.snapshotPath, std::ios::binary | std::ios::app);
        if (!probe) throw OptionError("--snapshot " + outputs.snapshotPath + ": cannot open the file for writing");
    }
    if (!outputs.recordPath.empty()) {
        if (!io::isRecordingPath(outputs.recordPath)) {
            throw OptionError("--record " + outputs.recordPath + ": unknown recording format (use a .glb or .html file name)");
        }
        std::ofstream probe(outputs.recordPath, std::ios::binary | std::ios::app);
        if (!probe) throw OptionError("--record " + outputs.recordPath + ": cannot open the file for writing");
    }
    if (!outputs.plotPath.empty()) {
        // The plot is SVG only: a .png full of SVG opens nowhere.
        std::string extension = std::filesystem::path(outputs.plotPath).extension().string();
        for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (extension != ".svg") {
            throw OptionError("--plot " + outputs.plotPath + ": the plot is an SVG image, give a file name ending in .svg");
        }
        // Fail before the run, not after it.
        std::ofstream probe(outputs.plotPath, std::ios::binary | std::ios::app);
        if (!probe) throw OptionError("--plot " + outputs.plotPath + ": cannot open the file for writing");
    }
    if (outputs.csvParticles && outputs.csvPath.empty()) throw OptionError("--csv-particles: needs --csv FILE to write the rows to");
    File csv;
    if (!outputs.csvPath.empty()) {
        csv.reset(std::fopen(outputs.csvPath.c_str(), "wb"));
        if (!csv) throw OptionError("--csv " + outputs.csvPath + ": cannot open the file for writing");
        static thread_local char buffer[1 << 16];
        std::setvbuf(csv.get(), buffer, _IOFBF, sizeof buffer);
        std::fputs("step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", csv.get());
    }

    RunResult result;
    result.world = std::move(built);
    result.handles = handles;
    World& w = result.world;
    const auto saveIfAsked = [&] {
        if (outputs.snapshotAt && static_cast<long long>(w.stepCount()) == *outputs.snapshotAt) {
            try {
                saveSnapshot(w, outputs.snapshotPath, runRecord(scene));
            } catch (const Error& e) {
                throw OptionError(std::string("--snapshot ") + e.what());
            }
        }
    };
    saveIfAsked();
    World& world = w;
    result.initialEnergy = world.energy();
    const bool plot = !outputs.plotPath.empty();
    if (plot) {
        result.samples.reserve(static_cast<std::size_t>(scene.steps) + 1);
        result.samples.push_back(sample(world));
    }
    if (csv) writeCsvRows(csv.get(), world, scene, result.handles, world.stepCount());
    if (csv && outputs.csvParticles) writeCsvParticleRows(csv.get(), world, scene, result.handles, world.stepCount());
    if (observer) observer(world, result.handles, world.stepCount());
    std::optional<io::Recorder> recorder;
    if (!outputs.recordPath.empty()) {
        recorder.emplace(world, io::RecordOptions{.title = scene.sourceName.empty() ? "Fulcrum" : scene.sourceName});
        // Robot links are drawn as their URDF visuals (docs/robots.md).
        for (std::size_t i = 0; i < scene.bodies.size() && i < result.handles.bodies.size(); ++i) {
            if (!scene.bodies[i].visuals.empty()) recorder->setVisuals(result.handles.bodies[i], scene.bodies[i].visuals);
        }
        recorder->capture(world);
    }

    checkReportFinite(world, scene, result.handles, world.stepCount());
    ProgressBar progress(outputs.progress, scene.steps);
    const auto start = std::chrono::steady_clock::now();
    const std::uint64_t firstStep = world.stepCount();
    for (int i = 1; i <= scene.steps; ++i) {
        // Steps are numbered as the world counts them, so a resumed run goes on
        // where the snapshot left off (CSV rows, --snapshot-at).
        const std::uint64_t step = firstStep + static_cast<std::uint64_t>(i);
        try {
            world.step(scene.dt);
        } catch (const NumericalError& e) {
            // The engine names the body; add the step unless it says it already.
            const std::string what = e.what();
            if (what.find("step") != std::string::npos) throw;
            throw NumericalError("at step " + std::to_string(step) + " (t = " + formatNumber(world.time()) + " s): " + what);
        }
        checkReportFinite(world, scene, result.handles, step);
        addProfile(result, world.lastStepProfile());
        for (const ContactHitEvent& hit : world.contactHitEvents()) {
            if (result.hits.size() < RunResult::kMaxReportedHits) {
                result.hits.push_back({step, hit});
            } else {
                ++result.hitsLeftOut;
            }
        }
        saveIfAsked();
        if (csv) writeCsvRows(csv.get(), world, scene, result.handles, step);
        if (csv && outputs.csvParticles) writeCsvParticleRows(csv.get(), world, scene, result.handles, step);
        if (plot) result.samples.push_back(sample(world));
        if (recorder) recorder->capture(world);
        if (observer) observer(world, result.handles, step);
        progress.update(i);
    }
    result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    if (csv && (std::fflush(csv.get()) != 0 || std::ferror(csv.get()))) {
        throw OptionError("--csv " + outputs.csvPath + ": error while writing the file");
    }
    if (recorder) recorder->write(outputs.recordPath);
    if (plot) {
        std::ofstream out(outputs.plotPath, std::ios::binary | std::ios::trunc);
        out << plotSvg(scene, result.samples);
        if (!out) throw OptionError("--plot " + outputs.plotPath + ": error while writing the file");
    }
    return result;
}

namespace {

// j.dump(2), except that an array of plain values (a vector, a quaternion) is
// written on one line: `"position": [1.5, 0.25, 0]`. Each value is written by
// nlohmann's own dump, so the numbers are the same text, bit for bit.
void writeReadableJson(std::string& out, const ojson& j, std::size_t indent) {
    if (!j.is_structured() || j.empty()) {
        out += jsonText(j);
        return;
    }
    if (j.is_array() && std::all_of(j.begin(), j.end(), [](const ojson& e) { return e.is_primitive(); })) {
        out += '[';
        for (std::size_t i = 0; i < j.size(); ++i) {
            if (i > 0) out += ", ";
            out += jsonText(j[i]);
        }
        out += ']';
        return;
    }
    out += j.is_object() ? "{\n" : "[\n";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
        if (!first) out += ",\n";
        first = false;
        out.append(indent + 2, ' ');
        if (j.is_object()) out += jsonText(ojson(it.key())) + ": ";
        writeReadableJson(out, it.value(), indent + 2);
    }
    out += '\n';
    out.append(indent, ' ');
    out += j.is_object() ? '}' : ']';
}

// The phases of StepProfile, in pipeline order, with their report names.
struct ProfilePhase {
    const char* name;
    double StepProfile::*field;
};
constexpr ProfilePhase kProfilePhases[] = {
    {"collide", &StepProfile::collide},       {"prepare", &StepProfile::prepare}, {"solve", &StepProfile::solve},
    {"store", &StepProfile::store},           {"continuous", &StepProfile::continuous},
    {"particles", &StepProfile::particles},   {"sleep", &StepProfile::sleep},     {"finish", &StepProfile::finish},
};

}  // namespace

std::string runReportJson(const Scene& scene, const RunResult& result, bool withProfile) {
    const World& world = result.world;
    ojson j;
    j["steps"] = world.stepCount();
    j["time"] = static_cast<double>(world.time());
    j["wall_seconds"] = result.wallSeconds;
    ojson bodies = ojson::array();
    for (std::size_t i = 0; i < result.handles.bodies.size(); ++i) {
        const BodyId id = result.handles.bodies[i];
        ojson b;
        b["name"] = sceneBodyName(scene, i);
        b["position"] = vec(world.position(id));
        b["orientation"] = quat(world.orientation(id));
        b["linear_velocity"] = vec(world.linearVelocity(id));
        b["angular_velocity"] = vec(world.angularVelocity(id));
        b["sleeping"] = !world.isAwake(id);
        bodies.push_back(std::move(b));
    }
    j["bodies"] = std::move(bodies);
    const EnergyReport e = world.energy();
    j["energy"] = ojson{{"kinetic", e.kinetic}, {"potential", e.potential}, {"total", e.total}};
    j["momentum"] = ojson{{"linear", vec(world.linearMomentum())}, {"angular", vec(world.angularMomentum())}};
    const auto nameOf = [&](BodyId id) -> ojson {
        for (std::size_t i = 0; i < result.handles.bodies.size(); ++i) {
            if (result.handles.bodies[i] == id) return sceneBodyName(scene, i);
        }
        return nullptr;  // the static world
    };
    ojson contacts = ojson::array();
    for (const ContactReport& c : world.contacts()) {
        ojson points = ojson::array();
        for (const Vec3& p : c.points) points.push_back(vec(p));
        contacts.push_back(ojson{{"body_a", nameOf(c.bodyA)},
                                 {"body_b", nameOf(c.bodyB)},
                                 {"normal", vec(c.normal)},
                                 {"depth", num(c.depth)},
                                 {"points", std::move(points)},
                                 {"normal_impulse", num(c.normalImpulse)},
                                 {"force", vec(c.force)}});
    }
    j["contacts"] = std::move(contacts);
    // Impacts faster than world.hit_event_threshold over the whole run, in
    // step order (docs/cli.md): for sounds and damage, as World::contactHitEvents.
    ojson hits = ojson::array();
    for (const RunHit& h : result.hits) {
        hits.push_back(ojson{{"step", h.step},
                             {"body_a", nameOf(h.event.bodyA)},
                             {"body_b", nameOf(h.event.bodyB)},
                             {"point", vec(h.event.point)},
                             {"normal", vec(h.event.normal)},
                             {"approach_speed", num(h.event.approachSpeed)}});
    }
    j["hits"] = std::move(hits);
    if (result.hitsLeftOut > 0) j["hits_left_out"] = result.hitsLeftOut;
    ojson joints = ojson::array();
    for (std::size_t i = 0; i < result.handles.joints.size(); ++i) {
        const JointId id = result.handles.joints[i];
        // A broken joint is gone from the world; report it with a null error.
        ojson error = world.isValid(id) ? ojson(num(world.jointError(id))) : ojson(nullptr);
        ojson joint{{"name", jointName(scene, i)}, {"error", std::move(error)}};
        // Along the joint's axis (docs/robots.md): rad or m, rad/s or m/s, N m or N.
        if (world.isValid(id)) {
            joint["position"] = num(world.jointPosition(id));
            joint["velocity"] = num(world.jointVelocity(id));
            joint["torque"] = num(world.jointEffort(id));
            // Six-DOF joints: per axis (x, y, z in m, m/s, N; then rx, ry, rz in rad, rad/s, N m).
            if (world.jointDef(id).type == JointType::SixDof) {
                const SixDofReading r = world.sixDofReading(id);
                const auto six = [&](const std::array<Real, kSixDofAxes>& v) {
                    ojson a = ojson::array();
                    for (const Real x : v) a.push_back(num(x));
                    return a;
                };
                joint["axis_positions"] = six(r.position);
                joint["axis_velocities"] = six(r.velocity);
                joint["axis_efforts"] = six(r.effort);
            }
        }
        joints.push_back(std::move(joint));
    }
    j["joints"] = std::move(joints);
    // docs/cli.md: {"name", "particles", "centroid", "max_stretch", "mean_stretch", "max_penetration"}, ropes then cloths.
    ojson systems = ojson::array();
    for (int kind = 0; kind < 2; ++kind) {
        const std::vector<ParticleSystemId>& ids = kind == 0 ? result.handles.ropes : result.handles.cloths;
        for (std::size_t k = 0; k < ids.size(); ++k) {
            const ParticleReport r = world.particleReport(ids[k]);
            systems.push_back(ojson{{"name", particleSystemName(scene, kind == 1, k)},
                                    {"particles", r.particles},
                                    {"centroid", vec(r.centroid)},
                                    {"max_stretch", num(r.maxStretch)},
                                    {"mean_stretch", num(r.meanStretch)},
                                    {"max_penetration", num(r.maxPenetration)}});
        }
    }
    j["particle_systems"] = std::move(systems);
    // docs/cli.md: {"name", "position", "on_ground", "ground_normal"} (plus the
    // ground state and velocity), only when the scene has characters.
    if (!result.handles.characters.empty()) {
        ojson characters = ojson::array();
        for (const CharacterId id : result.handles.characters) {
            const CharacterState s = world.characterState(id);
            characters.push_back(ojson{{"name", world.name(id)},
                                       {"position", vec(s.position)},
                                       {"on_ground", s.ground == GroundState::OnGround},
                                       {"ground_normal", vec(s.groundNormal)},
                                       {"ground", toString(s.ground)},
                                       {"velocity", vec(s.velocity)}});
        }
        j["characters"] = std::move(characters);
    }
    // docs/cli.md: {"name", "position", "speed", "wheels": [{"in_contact",
    // "suspension_length"}]} (plus the gear and wheel spin), only when the scene has vehicles.
    if (!result.handles.vehicles.empty()) {
        ojson vehicles = ojson::array();
        for (const VehicleId id : result.handles.vehicles) {
            const VehicleState s = vehicleState(world, id);
            ojson wheels = ojson::array();
            for (const WheelState& w : s.wheels) {
                wheels.push_back(ojson{{"in_contact", w.inContact},
                                       {"suspension_length", num(w.suspensionLength)},
                                       {"angular_velocity", num(w.angularVelocity)},
                                       {"steer_angle", num(w.steerAngle)}});
            }
            vehicles.push_back(ojson{{"name", vehicleDef(world, id).name},
                                     {"position", vec(s.position)},
                                     {"speed", num(s.speed)},
                                     {"gear", s.gear},
                                     {"wheels", std::move(wheels)}});
        }
        j["vehicles"] = std::move(vehicles);
    }
    // Only when the world warned (an extension: the object is unchanged otherwise).
    if (!world.warnings().empty()) {
        ojson warnings = ojson::array();
        for (const WorldWarning& w : world.warnings()) warnings.push_back(ojson{{"step", w.step}, {"message", w.message}});
        j["warnings"] = std::move(warnings);
    }
    if (withProfile) {
        const StepProfile& p = result.profile;
        const double steps = result.profiledSteps > 0 ? static_cast<double>(result.profiledSteps) : 1.0;
        ojson prof{{"steps", result.profiledSteps}, {"ms_per_step", p.total / steps}};
        for (const ProfilePhase& phase : kProfilePhases) prof[phase.name] = p.*(phase.field) / steps;
        prof["max_awake_bodies"] = p.awakeBodies;
        prof["max_contact_constraints"] = p.contactConstraints;
        prof["max_joint_constraints"] = p.jointConstraints;
        prof["workers"] = p.workers;
        prof["max_contact_pairs"] = p.contactPairs;
        prof["contact_pair_limit"] = p.contactPairLimit;
        prof["steps_over_pair_limit"] = result.stepsOverPairLimit;
        j["profile"] = std::move(prof);
    }
    std::string text;
    writeReadableJson(text, j, 0);
    return text + "\n";
}


void addProfile(RunResult& result, const StepProfile& step) {
    StepProfile& sum = result.profile;
    sum.total += step.total;
    for (const ProfilePhase& phase : kProfilePhases) sum.*(phase.field) += step.*(phase.field);
    sum.awakeBodies = std::max(sum.awakeBodies, step.awakeBodies);
    sum.contactConstraints = std::max(sum.contactConstraints, step.contactConstraints);
    sum.jointConstraints = std::max(sum.jointConstraints, step.jointConstraints);
    sum.workers = std::max(sum.workers, step.workers);
    sum.contactPairs = std::max(sum.contactPairs, step.contactPairs);
    sum.contactPairLimit = step.contactPairLimit;  // the last step's
    sum.pairsLeftOut = std::max(sum.pairsLeftOut, step.pairsLeftOut);
    sum.bodiesOverPairLimit = std::max(sum.bodiesOverPairLimit, step.bodiesOverPairLimit);
    ++result.profiledSteps;
    if (step.bodiesOverPairLimit > 0) {
        if (result.stepsOverPairLimit++ == 0) result.firstStepOverPairLimit = result.world.stepCount();
    }
}

std::string profileSummary(const RunResult& result) {
    const StepProfile& p = result.profile;
    std::ostringstream s;
    char line[256];
    const double steps = result.profiledSteps > 0 ? static_cast<double>(result.profiledSteps) : 1.0;
    std::snprintf(line, sizeof line,
                  "profile: %llu steps, %.4f ms per step (mean); at most %u bodies awake, %u contact and %u joint "
                  "constraints, %u worker%s\n",
                  static_cast<unsigned long long>(result.profiledSteps), p.total / steps, p.awakeBodies,
                  p.contactConstraints, p.jointConstraints, p.workers, p.workers == 1 ? "" : "s");
    s << line;
    for (const ProfilePhase& phase : kProfilePhases) {
        const double ms = p.*(phase.field);
        std::snprintf(line, sizeof line, "  %-10s %10.4f ms/step %6.1f %%\n", phase.name, ms / steps,
                      p.total > 0 ? 100 * ms / p.total : 0.0);
        s << line;
    }
    return s.str();
}

// The pairs the solver left overlapping deeper than a tenth of the smaller
// body (World::deepOverlaps), named: a run whose bodies sank into each other
// (a mass ratio beyond what the solver holds) must not read as a success.
namespace {
std::string deepOverlapWarning(const Scene& scene, const RunResult& result) {
    const std::vector<DeepOverlap> deep = result.world.deepOverlaps();
    if (deep.empty()) return {};
    const auto nameOf = [&](BodyId id) {
        for (std::size_t i = 0; i < result.handles.bodies.size(); ++i) {
            if (result.handles.bodies[i] == id) return sceneBodyName(scene, i);
        }
        return std::string("(unnamed body)");
    };
    std::ostringstream s;
    s << "  warning: " << deep.size() << (deep.size() == 1 ? " pair of bodies stays" : " pairs of bodies stay")
      << " overlapped deeper than 10 % of the smaller body (the solver did not hold them apart; a mass ratio"
         " beyond its limit? docs/solver.md, \"Mass ratios\"):\n";
    constexpr std::size_t kShown = 10;
    char line[512];
    for (std::size_t k = 0; k < std::min(deep.size(), kShown); ++k) {
        std::snprintf(line, sizeof line, "    %s and %s: %.4g m deep (size %.4g m)\n", nameOf(deep[k].bodyA).c_str(),
                      nameOf(deep[k].bodyB).c_str(), double(deep[k].depth), double(deep[k].size));
        s << line;
    }
    if (deep.size() > kShown) s << "    ... and " << deep.size() - kShown << " more pairs\n";
    return s.str();
}
}  // namespace

std::string runSummary(const Scene& scene, const RunResult& result, const std::string& label) {
    const World& world = result.world;
    std::ostringstream s;
    char line[512];
    std::snprintf(line, sizeof line, "%s: %llu steps of %s s (t = %.4g s), %s, %d substeps, %.3g s wall\n", label.c_str(),
                  static_cast<unsigned long long>(world.stepCount()), formatNumber(scene.dt).c_str(), double(world.time()),
                  toString(scene.world.integrator), scene.world.substeps, result.wallSeconds);
    s << line;
    std::size_t width = 4;
    for (std::size_t i = 0; i < result.handles.bodies.size(); ++i) width = std::max(width, sceneBodyName(scene, i).size());
    const std::size_t shown = std::min<std::size_t>(result.handles.bodies.size(), 20);
    for (std::size_t i = 0; i < shown; ++i) {
        const BodyId id = result.handles.bodies[i];
        const Vec3 p = world.position(id), v = world.linearVelocity(id), w = world.angularVelocity(id);
        std::snprintf(line, sizeof line, "  %-*s  position (%9.4f, %9.4f, %9.4f) m   velocity (%8.3f, %8.3f, %8.3f) m/s   |w| %7.3f rad/s%s\n",
                      static_cast<int>(width), sceneBodyName(scene, i).c_str(), double(p.x), double(p.y), double(p.z), double(v.x),
                      double(v.y), double(v.z), double(length(w)), world.isAwake(id) ? "" : "  (sleeping)");
        s << line;
    }
    if (shown < result.handles.bodies.size()) s << "  ... and " << result.handles.bodies.size() - shown << " more bodies\n";
    const EnergyReport e = world.energy();
    std::snprintf(line, sizeof line, "  energy: kinetic %.6g J, potential %.6g J, total %.6g J (at start %.6g J)\n", e.kinetic,
                  e.potential, e.total, result.initialEnergy.total);
    s << line;
    std::snprintf(line, sizeof line, "  momentum: |p| %.6g kg m/s, |L| %.6g kg m^2/s; %zu contact manifolds, %zu joints\n",
                  double(length(world.linearMomentum())), double(length(world.angularMomentum())), world.contacts().size(),
                  result.handles.joints.size());
    s << line;
    for (const WorldWarning& warning : world.warnings()) s << "  warning (step " << warning.step << "): " << warning.message << "\n";
    if (result.stepsOverPairLimit > 0) {
        const StepProfile& p = result.profile;
        std::snprintf(line, sizeof line,
                      "  contact pair limit %u (world.max_contact_pairs) held new pairs back in %llu of %llu steps, "
                      "first in step %llu; at most %u pairs held, at most %u bodies waiting for pairs\n",
                      p.contactPairLimit, static_cast<unsigned long long>(result.stepsOverPairLimit),
                      static_cast<unsigned long long>(result.profiledSteps),
                      static_cast<unsigned long long>(result.firstStepOverPairLimit), p.contactPairs, p.bodiesOverPairLimit);
        s << line;
    }
    for (int kind = 0; kind < 2; ++kind) {
        const std::vector<ParticleSystemId>& ids = kind == 0 ? result.handles.ropes : result.handles.cloths;
        for (std::size_t k = 0; k < ids.size(); ++k) {
            const ParticleReport r = world.particleReport(ids[k]);
            std::snprintf(line, sizeof line,
                          "  %s %s: %zu particles, centroid (%.4f, %.4f, %.4f) m, stretch max %.3g %% mean %.3g %%, deepest %.3g mm\n",
                          kind == 0 ? "rope" : "cloth", particleSystemName(scene, kind == 1, k).c_str(), r.particles,
                          double(r.centroid.x), double(r.centroid.y), double(r.centroid.z), 100.0 * double(r.maxStretch),
                          100.0 * double(r.meanStretch), 1000.0 * double(r.maxPenetration));
            s << line;
        }
    }
    s << deepOverlapWarning(scene, result);
    return s.str();
}

namespace {
std::string oneLine(std::string s) {
    for (char& c : s) {
        if (c == '\n' || c == '\r') c = ' ';
    }
    return s;
}
}  // namespace

int runCommand(const std::optional<std::string>& scenePath, const RunOverrides& overrides, const RunOutputs& outputs,
               std::ostream& out, std::ostream& err) {
    Scene scene;
    const bool resume = overrides.resumePath.has_value();
    const bool demoRun = !scenePath && !resume;
    const std::string label = resume ? *overrides.resumePath + " (resumed)" : scenePath ? *scenePath : "built-in demo";
    try {
        if (resume && scenePath) throw OptionError("--resume: continues a saved run; give it without a scene file (" + *scenePath + ")");
        DemoChecks demo;
        StepObserver observer;
        if (demoRun) {
            observer = [&demo](const World& w, const SceneHandles& h, std::uint64_t step) { demo.observe(w, h, step); };
        }
        RunResult result;
        if (resume) {
            std::string userData;
            World world;
            try {
                world = loadSnapshot(*overrides.resumePath, &userData);
            } catch (const Error& e) {
                throw OptionError(e.what());  // names the file, the byte and the part
            }
            SceneHandles handles;
            scene = resumeScene(world, userData, *overrides.resumePath, handles);
            const bool knowsDt = scene.dt > 0;
            if (!knowsDt) scene.dt = kSceneDefaultDt;
            applyOverrides(scene, overrides);
            if (!knowsDt && !overrides.dt) {
                throw OptionError("--resume " + *overrides.resumePath +
                                  ": the snapshot does not record its time step (it was not written by fulcrum run); give --dt");
            }
            // Settings the options changed (the same values leave the run bit-identical).
            world.setIntegrator(scene.world.integrator);
            world.setSubsteps(scene.world.substeps);
            world.setThreadCount(scene.world.threads);
            world.setPushOutGrownOverlaps(scene.world.pushOutGrownOverlaps);
            result = runWorld(std::move(world), handles, scene, outputs, observer);
        } else {
            if (overrides.fixedBase && !(scenePath && isUrdfPath(*scenePath))) {
                throw OptionError("--fixed-base: only for a URDF robot file (fulcrum run ROBOT.urdf --fixed-base)");
            }
            if (scenePath && isUrdfPath(*scenePath)) {
                scene = urdfRunScene(*scenePath, overrides.fixedBase);
            } else {
                scene = scenePath ? loadScene(*scenePath) : demoScene();
            }
            applyOverrides(scene, overrides);
            result = runScene(scene, outputs, observer);
        }
        if (outputs.json) {
            out << runReportJson(scene, result, outputs.profile);
        } else {
            out << runSummary(scene, result, "fulcrum: " + label);
            if (demoRun) out << demo.report(scene, result);
            if (outputs.profile) out << profileSummary(result);
        }
        out.flush();
        return 0;
    } catch (const SceneError& e) {
        err << "fulcrum: " << oneLine(e.what()) << "\n";
        return 2;
    } catch (const OptionError& e) {
        err << "fulcrum: " << oneLine(e.what()) << "\n";
        return 2;
    } catch (const NumericalError& e) {
        err << "fulcrum: " << label << ": simulation stopped, the state became non-finite: " << oneLine(e.what()) << "\n";
        return 3;
    } catch (const Error& e) {
        err << "fulcrum: " << label << ": " << oneLine(e.what()) << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        // Outside World::step (which says more): loading, outputs, recording.
        err << "fulcrum: " << label << ": out of memory\n";
        return 2;
    } catch (const std::exception& e) {
        // A backstop, not a way to report input errors (those are Errors
        // above): whatever escaped is a bug, still told in one line.
        err << "fulcrum: " << label << ": internal error: " << oneLine(e.what()) << "\n";
        return 1;
    }
}

}  // namespace fulcrum::detail
