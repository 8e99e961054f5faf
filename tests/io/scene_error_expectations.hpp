#pragma once
// Shared by the scene-file tests: parse a text that must fail, and check the
// SceneError's path, line and reason.
#include <gtest/gtest.h>

#include <string>

#include "fulcrum/scene.hpp"

namespace fulcrum::test {

// Parses `text` (as "test.json"), expects a SceneError and returns it.
inline SceneError parseError(const std::string& text) {
    try {
        parseScene(text, "test.json");
    } catch (const SceneError& e) {
        return e;
    }
    ADD_FAILURE() << "no SceneError for: " << text;
    return SceneError("", "", 0, 0, "");
}

// Expects parsing to fail at `path` (and `line` when > 0) with a reason
// containing `reason`, in a one-line message naming the file.
inline void expectError(const std::string& text, const std::string& path, const std::string& reason, int line = 0) {
    const SceneError e = parseError(text);
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_NE(e.reason().find(reason), std::string::npos) << "reason '" << e.reason() << "' lacks '" << reason << "'";
    if (line > 0) {
        EXPECT_EQ(e.line(), line) << e.what();
    }
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "what() must be one line";
    EXPECT_NE(std::string(e.what()).find("test.json"), std::string::npos) << e.what();
}

}  // namespace fulcrum::test
