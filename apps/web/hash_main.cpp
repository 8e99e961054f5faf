// fulcrum_web_hash SCENE.json STEPS [ROUNDS]: the state hash (fw_state_hash)
// of a scene after STEPS steps, stepped through the JavaScript module's own C
// API (fulcrum_web.cpp) in the native build; the sandbox's browser test
// compares the page's hash with it (docs/browser.md). With ROUNDS, also the
// fastest round's milliseconds per step (the world built anew each round),
// the native side of docs/benchmarks.md's WebAssembly table.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

extern "C" {
const char* fw_last_error();
int fw_world_from_scene(const char* sceneJson);
int fw_step(int handle, int count);
const char* fw_state_hash(int handle);
void fw_world_destroy(int handle);
}

int main(int argc, char** argv) {
    if (argc != 3 && argc != 4) {
        std::fprintf(stderr, "usage: fulcrum_web_hash SCENE.json STEPS [ROUNDS]\n");
        return 2;
    }
    std::ifstream file(argv[1]);
    if (!file) {
        std::fprintf(stderr, "fulcrum_web_hash: cannot read %s\n", argv[1]);
        return 1;
    }
    std::ostringstream text;
    text << file.rdbuf();
    const int steps = std::atoi(argv[2]), rounds = argc == 4 ? std::max(std::atoi(argv[3]), 1) : 1;
    double best = 1e300;
    for (int round = 0; round < rounds; ++round) {
        const int world = fw_world_from_scene(text.str().c_str());
        const auto start = std::chrono::steady_clock::now();
        if (world == 0 || fw_step(world, steps) != 0) {
            std::fprintf(stderr, "fulcrum_web_hash: %s\n", fw_last_error());
            return 1;
        }
        best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        if (round + 1 == rounds) {
            if (argc == 4) std::printf("%s %.4f\n", fw_state_hash(world), best / std::max(steps, 1));
            else std::printf("%s\n", fw_state_hash(world));
        }
        fw_world_destroy(world);
    }
    return 0;
}
