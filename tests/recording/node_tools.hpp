#pragma once
// Running the node scripts of viewer/test from GoogleTest: locating node,
// Chromium and the node packages (so a test can skip with the reason when one
// is missing) and running a command to collect its output and exit status.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

namespace fulcrum::io::node_tools {

namespace fs = std::filesystem;

inline fs::path sourceDir() {
    const char* env = std::getenv("FULCRUM_SOURCE_DIR");
    return env ? fs::path(env) : fs::path(FULCRUM_SOURCE_DIR);
}

inline fs::path viewerDir() { return sourceDir() / "viewer"; }

// The first executable called `name` on PATH, or empty.
inline fs::path findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    const std::string dirs = path ? path : "";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', start), dirs.size());
        const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
        std::error_code ec;
        if (!candidate.parent_path().empty() && fs::is_regular_file(candidate, ec)) return candidate;
        start = end + 1;
    }
    return {};
}

inline bool hasNodePackage(const std::string& package) { return fs::exists(viewerDir() / "node_modules" / package); }

inline std::string quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

struct RunResult {
    int exitCode = -1;       // -1 if the process did not exit normally
    std::string output;      // stdout and stderr
};

inline RunResult run(const std::string& command) {
    RunResult result;
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) result.output += buffer.data();
    const int status = pclose(pipe);
    if (WIFEXITED(status)) result.exitCode = WEXITSTATUS(status);
    return result;
}

}  // namespace fulcrum::io::node_tools
