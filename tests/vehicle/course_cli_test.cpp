// scenes/course.json through the command line: a car's lap and a character
// on stairs and a turntable in one run, reported by --json (docs/cli.md).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(CourseCli, CarAndCharacterInTheJson) {
    const fs::path dir = fs::temp_directory_path() / ("fulcrum_course_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path out = dir / "out.json";
    const std::string cmd = std::string("cd '") + FULCRUM_SOURCE_DIR + "' && '" + FULCRUM_CLI_PATH +
                            "' run scenes/course.json --json >'" + out.string() + "' </dev/null";
    const int raw = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0);
    const nlohmann::json j = nlohmann::json::parse(readFile(out));
    fs::remove_all(dir);

    ASSERT_EQ(j["characters"].size(), 1u);
    const auto& hero = j["characters"][0];
    EXPECT_EQ(hero["name"], "hero");
    EXPECT_TRUE(hero["on_ground"].get<bool>());
    EXPECT_NEAR(hero["position"][1].get<double>(), 1.0 + 0.91, 0.03);  // back on the turntable after the jump
    EXPECT_NEAR(hero["ground_normal"][1].get<double>(), 1.0, 1e-3);

    ASSERT_EQ(j["vehicles"].size(), 1u);
    const auto& car = j["vehicles"][0];
    EXPECT_EQ(car["name"], "car");
    EXPECT_LT(std::abs(car["speed"].get<double>()), 0.1);  // braked to a stop at the end of the lap
    ASSERT_EQ(car["wheels"].size(), 4u);
    for (const auto& w : car["wheels"]) {
        EXPECT_TRUE(w["in_contact"].get<bool>());
        EXPECT_GT(w["suspension_length"].get<double>(), 0.0);
        EXPECT_LT(w["suspension_length"].get<double>(), 0.3);
    }
}

}  // namespace
