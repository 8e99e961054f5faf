#pragma once
// `fulcrum run`, as a library: applying command-line overrides to a Scene,
// running it, and the outputs (--json report, --csv rows, --plot SVG, the human
// summary). apps/fulcrum/main.cpp only parses arguments and calls runCommand,
// so tests can drive all of this without a process.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum::detail {

// A bad command-line option value; what() is one line naming the option.
class OptionError : public Error {
public:
    using Error::Error;
};

// Options that override the scene's world settings.
struct RunOverrides {
    std::optional<long long> steps;
    std::optional<double> dt;
    std::optional<long long> substeps;
    std::optional<std::string> integrator;
    std::optional<long long> threads;
    // --push-out-grown-overlaps[=true|false]: WorldDef::pushOutGrownOverlaps
    // (the scene's world.push_out_grown_overlaps).
    std::optional<bool> pushOutGrownOverlaps;
    // --resume FILE: continue the run saved in a snapshot instead of loading a
    // scene (--steps then counts the further steps; default: the rest of the
    // original run).
    std::optional<std::string> resumePath;
    // --fixed-base: a URDF file run directly gets its root link static.
    bool fixedBase = false;
};
// Validates the overrides and applies them; throws OptionError.
void applyOverrides(Scene& scene, const RunOverrides& overrides);
// The value of a whole-number option ("--steps", "--substeps", "--threads")
// from its text; throws OptionError naming the option and its range, with the
// text as written (also when it overflows a long long).
long long parseIntegerOption(std::string_view name, const std::string& text);

struct RunOutputs {
    bool json = false;        // report on stdout as one JSON object
    std::string csvPath;      // empty: no CSV
    bool csvParticles = false;  // --csv-particles: also a row per rope/cloth particle ("r1[3]")
    std::string plotPath;     // empty: no SVG
    std::string recordPath;   // empty: no recording (.glb or .html)
    bool progress = false;    // progress bar on stderr (the caller checks it is a terminal)
    std::string snapshotPath;            // --snapshot FILE: where --snapshot-at writes
    std::optional<long long> snapshotAt; // --snapshot-at N: the world's state after step N (0: before the first)
    bool profile = false;     // --profile: where the step time went (World::lastStepProfile, summed)
};

struct RunSample {
    double time = 0;
    EnergyReport energy;
    double linearMomentum = 0;   // |p|, kg m/s
    double angularMomentum = 0;  // |L| about the origin, kg m^2/s
};

// An impact of the run (World::contactHitEvents after each step), for --json.
struct RunHit {
    std::uint64_t step = 0;
    ContactHitEvent event;
};

struct RunResult {
    World world;
    SceneHandles handles;
    double wallSeconds = 0;
    EnergyReport initialEnergy;
    std::vector<RunSample> samples;  // step 0..N, only when a plot was asked for
    StepProfile profile;             // the run's steps' World::lastStepProfile, summed (counts: their maxima)
    std::uint64_t profiledSteps = 0;
    // Steps in which the contact pair limit held new pairs back (WorldDef::maxContactPairs), and the first.
    std::uint64_t stepsOverPairLimit = 0, firstStepOverPairLimit = 0;
    // Every step's hit events (WorldDef::hitEventThreshold), the first
    // kMaxReportedHits of them; the rest only counted.
    static constexpr std::size_t kMaxReportedHits = 10000;
    std::vector<RunHit> hits;
    std::uint64_t hitsLeftOut = 0;
};

// Called after every step (and once before the first, with step 0).
using StepObserver = std::function<void(const World&, const SceneHandles&, std::uint64_t step)>;

// Builds the scene's world and runs scene.steps steps of scene.dt, writing the
// CSV as it goes and the SVG at the end. Throws SceneError (the scene cannot be
// built), OptionError (an output file cannot be written) or NumericalError
// (the state went NaN; the message gives the step and names the body).
RunResult runScene(const Scene& scene, const RunOutputs& outputs, const StepObserver& observer = {});
// The same for a world built already (a resumed snapshot): `scene` gives dt,
// the number of steps and the names of `handles`' objects.
RunResult runWorld(World world, const SceneHandles& handles, const Scene& scene, const RunOutputs& outputs,
                   const StepObserver& observer = {});
// A loaded snapshot as the Scene the outputs need (names, body types, dt,
// remaining steps from the snapshot's run record), and its handles.
Scene resumeScene(const World& world, const std::string& userData, const std::string& source, SceneHandles& handles);

// The --json report (docs/cli.md).
// withProfile (--profile): plus a "profile" object (ms per step of each phase).
std::string runReportJson(const Scene& scene, const RunResult& result, bool withProfile = false);
// Adds one step's World::lastStepProfile to result.profile (runScene does, each step).
void addProfile(RunResult& result, const StepProfile& step);
// --profile's table: mean ms per step of each phase and its share of the step.
std::string profileSummary(const RunResult& result);
// A short human summary of a run.
std::string runSummary(const Scene& scene, const RunResult& result, const std::string& label);

// `fulcrum run ROBOT.urdf` (docs/robots.md): whether a path names a URDF
// file, and the scene run for one: the robot (z up, gravity -z), its lowest
// collider 1 mm above a ground plane at z = 0, drives off.
bool isUrdfPath(const std::string& path);
Scene urdfRunScene(const std::string& path, bool fixedBase);

// The built-in demo: a showcase of what the engine does (src/io/demo.cpp),
// each part checked in the summary.
Scene demoScene();

// Follows the demo while it runs (the flips of the spinning box, the
// projectile in flight, the pyramid's start) and reports each part against its
// analytic answer or its physical expectation.
class DemoChecks {
public:
    void observe(const World& world, const SceneHandles& handles, std::uint64_t step);
    std::string report(const Scene& scene, const RunResult& result) const;
    int flips() const { return flips_; }

private:
    int flips_ = 0;
    int lastSign_ = 0;
    std::vector<Vec3> pyramidStart_;  // the pyramid's boxes at step 0
    double projectileTime_ = -1;      // the projectile sampled in flight, at t = 1 s
    Vec3 projectileAt_;
    double carDistance_ = 0;          // the course's car: metres driven
    Vec3 carLast_;
};

// The whole `fulcrum run` command. Returns the exit status: 0 done, 2 bad
// input (one line on `err`), 3 the simulation produced NaN/inf.
int runCommand(const std::optional<std::string>& scenePath, const RunOverrides& overrides, const RunOutputs& outputs,
               std::ostream& out, std::ostream& err);

}  // namespace fulcrum::detail
