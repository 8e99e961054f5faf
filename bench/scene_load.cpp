// Loading scene files: the time to read and validate a file (loadScene) and
// to build its World (buildWorld), what `fulcrum run FILE --steps 0` does
// before its first step, for files of 10^4, 10^5 and 10^6 bodies, and the
// process's peak memory (resident set) while it does so. Results are in
// docs/benchmarks.md, "Loading scene files".
//
//   bench_scene_load [--bodies N[,N...]] [--rounds R] [--dir DIR] [--keep]
//
// Each file is written to DIR (the system's temporary folder by default) in
// the style of a generated scene, one body per line: a static ground box,
// then spheres and boxes alternating on a cubic grid 1 m apart, each named
// and with a mass, and a ball joint between one pair of neighbours in every
// thousand bodies. Each round loads the file in a fresh child process, so its
// peak resident set is that of one load alone (the parent only wrote the
// file); the fastest of the rounds is reported (noise only adds time), and
// the least CPU time of the rounds (user + system: on a shared machine wall
// time also counts the other processes' turns).
// Linux only (fork, /proc/self/status).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fulcrum/scene.hpp"

namespace {

using namespace fulcrum;

// Writes the benchmark scene of `bodies` bodies (at least 2) to `file`.
void writeGridScene(const std::filesystem::path& file, long bodies) {
    std::ofstream out(file);
    const long dynamic = bodies - 1;
    const long side = std::max(1L, static_cast<long>(std::ceil(std::cbrt(static_cast<double>(dynamic)))));
    out << "{\n  \"description\": \"bench/scene_load.cpp: " << bodies << " bodies on a grid\",\n"
        << "  \"world\": {\"gravity\": [0, -9.81, 0], \"steps\": 0},\n  \"bodies\": [\n"
        << "    {\"name\": \"ground\", \"type\": \"static\", \"shape\": {\"type\": \"box\", \"half_extents\": [" << side
        << ", 0.5, " << side << "]}, \"position\": [0, -0.5, 0]}";
    // Grid cell of dynamic body i, centred on the origin in x and z, resting on the ground.
    const auto cell = [side](long i) {
        return std::array<double, 3>{static_cast<double>(i % side - side / 2), static_cast<double>((i / side) % side) + 0.5,
                                     static_cast<double>(i / (side * side) - side / 2)};
    };
    for (long i = 0; i < dynamic; ++i) {
        const auto [x, y, z] = cell(i);
        const char* shape = i % 2 == 0 ? R"({"type": "sphere", "radius": 0.4})" : R"({"type": "box", "half_extents": [0.4, 0.4, 0.4]})";
        out << ",\n    {\"name\": \"b" << i << "\", \"shape\": " << shape << ", \"mass\": 1, \"position\": [" << x << ", " << y
            << ", " << z << "]}";
    }
    out << "\n  ],\n  \"joints\": [";
    // Neighbours along x (the next body on the grid), one pair per thousand bodies.
    for (long i = 0, written = 0; i + 1 < dynamic; i += 1000) {
        if ((i + 1) % side == 0) continue;
        const auto [x, y, z] = cell(i);
        out << (written++ ? ",\n" : "\n") << "    {\"type\": \"ball\", \"body_a\": \"b" << i << "\", \"body_b\": \"b" << i + 1
            << "\", \"anchor\": [" << x + 0.5 << ", " << y << ", " << z << "]}";
    }
    out << "\n  ]\n}\n";
    if (!out) {
        std::fprintf(stderr, "bench_scene_load: cannot write %s\n", file.string().c_str());
        std::exit(1);
    }
}

struct Timing {
    double loadSeconds = 0;   // loadScene: read, parse, validate
    double buildSeconds = 0;  // buildWorld
    double cpuSeconds = 0;    // user + system time of both (the machine may be shared)
    double peakMegabytes = 0; // VmHWM of the process
    std::size_t bodies = 0, joints = 0;
};

double peakResidentMegabytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;  // kB
    }
    return 0;
}

double cpuSecondsSoFar() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
    return seconds(u.ru_utime) + seconds(u.ru_stime);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Loads `file` in a child process and returns its figures.
Timing loadInChild(const std::filesystem::path& file) {
    int fds[2];
    if (pipe(fds) != 0) std::exit(1);
    const pid_t child = fork();
    if (child == 0) {
        close(fds[0]);
        Timing t;
        const double cpuAtStart = cpuSecondsSoFar();
        const auto start = std::chrono::steady_clock::now();
        const Scene scene = loadScene(file);
        t.loadSeconds = secondsSince(start);
        const auto built = std::chrono::steady_clock::now();
        const World world = buildWorld(scene);
        t.buildSeconds = secondsSince(built);
        t.cpuSeconds = cpuSecondsSoFar() - cpuAtStart;
        t.peakMegabytes = peakResidentMegabytes();
        t.bodies = world.bodyCount();
        t.joints = scene.joints.size();
        const ssize_t written = write(fds[1], &t, sizeof t);
        _exit(written == static_cast<ssize_t>(sizeof t) ? 0 : 1);  // the OS frees the world faster than its destructor
    }
    close(fds[1]);
    Timing t;
    const ssize_t got = read(fds[0], &t, sizeof t);
    close(fds[0]);
    int status = 0;
    waitpid(child, &status, 0);
    if (got != static_cast<ssize_t>(sizeof t) || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::fprintf(stderr, "bench_scene_load: loading %s failed\n", file.string().c_str());
        std::exit(1);
    }
    return t;
}

std::vector<long> parseSizes(const char* list) {
    std::vector<long> sizes;
    for (const char* p = list; *p;) {
        char* end = nullptr;
        const long n = std::strtol(p, &end, 10);
        if (end == p || n < 2) {
            std::fprintf(stderr, "bench_scene_load: --bodies takes counts of at least 2, separated by commas\n");
            std::exit(2);
        }
        sizes.push_back(n);
        p = *end == ',' ? end + 1 : end;
    }
    return sizes;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<long> sizes = {10000, 100000, 1000000};
    int rounds = 3;
    std::filesystem::path dir = std::filesystem::temp_directory_path();
    bool keep = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--bodies") == 0 && i + 1 < argc) sizes = parseSizes(argv[++i]);
        else if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) rounds = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--dir") == 0 && i + 1 < argc) dir = argv[++i];
        else if (std::strcmp(argv[i], "--keep") == 0) keep = true;
        else {
            std::fprintf(stderr, "usage: %s [--bodies N[,N...]] [--rounds R] [--dir DIR] [--keep]\n", argv[0]);
            return 2;
        }
    }
    std::printf("| bodies (joints) | file | load: read + parse | build world | total | bodies/s | CPU time | peak RSS |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (long n : sizes) {
        const std::filesystem::path file = dir / ("fulcrum_bench_load_" + std::to_string(n) + ".json");
        writeGridScene(file, n);
        Timing best;
        for (int r = 0; r < rounds; ++r) {
            const Timing t = loadInChild(file);
            if (r == 0 || t.loadSeconds + t.buildSeconds < best.loadSeconds + best.buildSeconds) best = t;
            best.cpuSeconds = r == 0 ? t.cpuSeconds : std::min(best.cpuSeconds, t.cpuSeconds);
            best.peakMegabytes = std::max(best.peakMegabytes, t.peakMegabytes);
        }
        const double total = best.loadSeconds + best.buildSeconds;
        std::printf("| %zu (%zu) | %.1f MB | %.3f s | %.3f s | %.3f s | %.3g | %.3f s | %.0f MB |\n", best.bodies, best.joints,
                    static_cast<double>(std::filesystem::file_size(file)) / 1e6, best.loadSeconds, best.buildSeconds, total,
                    static_cast<double>(best.bodies) / total, best.cpuSeconds, best.peakMegabytes);
        std::fflush(stdout);
        if (!keep) std::filesystem::remove(file);
    }
}
