// fulcrum_web_hash SCENE.json STEPS: the state hash (fw_state_hash) of a scene
// after STEPS steps, stepped through the JavaScript module's own C API
// (fulcrum_web.cpp) in the native build; the sandbox's browser test compares
// the page's hash with it (docs/browser.md).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

extern "C" {
const char* fw_last_error();
int fw_world_from_scene(const char* sceneJson);
int fw_step(int handle, int count);
const char* fw_state_hash(int handle);
}

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: fulcrum_web_hash SCENE.json STEPS\n");
        return 2;
    }
    std::ifstream file(argv[1]);
    if (!file) {
        std::fprintf(stderr, "fulcrum_web_hash: cannot read %s\n", argv[1]);
        return 1;
    }
    std::ostringstream text;
    text << file.rdbuf();
    const int world = fw_world_from_scene(text.str().c_str());
    if (world == 0 || fw_step(world, std::atoi(argv[2])) != 0) {
        std::fprintf(stderr, "fulcrum_web_hash: %s\n", fw_last_error());
        return 1;
    }
    std::printf("%s\n", fw_state_hash(world));
    return 0;
}
