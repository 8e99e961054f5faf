// The `fulcrum` command-line tool: argument parsing only; the command itself
// is fulcrum::detail::runCommand (src/io/run.cpp), so it is testable.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <string>

#include "io/run.hpp"

#ifndef FULCRUM_VERSION
#define FULCRUM_VERSION "unknown"
#endif

int main(int argc, char** argv) {
    CLI::App app{"Fulcrum: a 3D rigid-body physics engine. Scene format: docs/scene-format.md; this tool: docs/cli.md.", "fulcrum"};
    app.set_version_flag("--version", std::string("fulcrum ") + FULCRUM_VERSION);
    app.require_subcommand(0, 1);

    CLI::App* run = app.add_subcommand("run", "Run a scene file (or, without one, the built-in demo)");
    std::string scene;
    fulcrum::detail::RunOverrides overrides;
    fulcrum::detail::RunOutputs outputs;
    std::string steps, substeps, threads;  // whole numbers, converted by parseIntegerOption (it names the range)
    double dt = 0;
    std::string integrator;
    run->add_option("scene", scene, "Scene file (JSON) or URDF robot (.urdf); omit for the built-in demo");
    CLI::Option* stepsOpt = run->add_option("--steps", steps, "Number of steps (overrides world.steps)");
    CLI::Option* dtOpt = run->add_option("--dt", dt, "Time step in seconds (overrides world.dt)");
    CLI::Option* substepsOpt = run->add_option("--substeps", substeps, "Sub-steps per step (overrides world.substeps)");
    CLI::Option* integratorOpt =
        run->add_option("--integrator", integrator, "semi_implicit_euler, explicit_euler or verlet (overrides world.integrator)");
    CLI::Option* threadsOpt = run->add_option("--threads", threads, "Worker threads (results are identical for every count)");
    bool pushOut = false;
    CLI::Option* pushOutOpt = run->add_flag("--push-out-grown-overlaps", pushOut,
                                            "Push apart pairs that got deeper within a step (overrides world.push_out_grown_overlaps; "
                                            "=false turns it off)");
    run->add_flag("--json", outputs.json, "Print one JSON object with the final state on stdout");
    run->add_option("--csv", outputs.csvPath, "Write every step of every dynamic body to FILE (CSV)");
    run->add_flag("--csv-particles", outputs.csvParticles, "With --csv: also a row per rope and cloth particle (body \"r1[3]\")");
    run->add_option("--plot", outputs.plotPath, "Write energy and momentum over time to FILE.svg");
    run->add_option("--record", outputs.recordPath, "Record the run: FILE.glb (animated glTF 2.0) or FILE.html (self-contained replay page)");
    long long snapshotAt = 0;
    std::string resume;
    CLI::Option* snapshotAtOpt =
        run->add_option("--snapshot-at", snapshotAt, "Save the state after step N (0: before the first) to --snapshot FILE, and keep running");
    run->add_option("--snapshot", outputs.snapshotPath, "Snapshot file written by --snapshot-at (docs/snapshots.md)");
    run->add_flag("--profile", outputs.profile, "Report where the step time went: ms per step of each phase (summary table, or \"profile\" in --json)");
    run->add_flag("--fixed-base", overrides.fixedBase, "With a URDF robot file: its root link static (docs/robots.md)");
    CLI::Option* resumeOpt = run->add_option("--resume", resume, "Continue the run saved in a snapshot FILE (instead of a scene); --steps counts the further steps");

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line, exit status 2, like every other bad input.
        std::string what = e.what();
        for (char& c : what) {
            if (c == '\n') c = ' ';
        }
        std::cerr << "fulcrum: " << what << " (see fulcrum run --help)\n";
        return 2;
    }
    if (!run->parsed()) {
        std::cout << app.help();
        return 0;
    }
    try {
        if (*stepsOpt) overrides.steps = fulcrum::detail::parseIntegerOption("--steps", steps);
        if (*substepsOpt) overrides.substeps = fulcrum::detail::parseIntegerOption("--substeps", substeps);
        if (*threadsOpt) overrides.threads = fulcrum::detail::parseIntegerOption("--threads", threads);
    } catch (const fulcrum::detail::OptionError& e) {
        std::cerr << "fulcrum: " << e.what() << "\n";
        return 2;
    }
    if (*dtOpt) overrides.dt = dt;
    if (*integratorOpt) overrides.integrator = integrator;
    if (*pushOutOpt) overrides.pushOutGrownOverlaps = pushOut;
    if (*snapshotAtOpt) outputs.snapshotAt = snapshotAt;
    if (*resumeOpt) overrides.resumePath = resume;
    // A progress bar only for a person watching a terminal: never into a pipe,
    // and not when the JSON report goes to a pipe either.
    outputs.progress = isatty(fileno(stderr)) && !(outputs.json && !isatty(fileno(stdout)));

    const std::optional<std::string> scenePath = scene.empty() ? std::nullopt : std::optional<std::string>(scene);
    return fulcrum::detail::runCommand(scenePath, overrides, outputs, std::cout, std::cerr);
}
