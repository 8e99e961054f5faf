#pragma once
// Self-contained HTML replay page of a Recording: the page template and the
// bundled viewer (three.js + viewer/src/viewer.js, built into
// viewer/dist/viewer.js and embedded into this library at build time) with the
// recording inlined as JSON whose bulk arrays are deflated little-endian binary
// (base64), losslessly.
// The page loads nothing from the network. Format and controls:
// docs/recording.md.
#include <filesystem>
#include <string>

#include "io/recording_display.hpp"

namespace fulcrum::io {

// The page as one string. Throws fulcrum::Error for an invalid or empty recording.
std::string renderHtml(const Recording& recording);

// The recording as the JSON document the page embeds (for tools and tests).
std::string recordingJson(const Recording& recording);

// Writes renderHtml's page; throws fulcrum::Error naming the file if it cannot be written.
void writeHtml(const Recording& recording, const std::filesystem::path& path);

namespace detail {
std::string viewerScript();    // generated at build time (viewer/embed_assets.cmake)
std::string viewerTemplate();
}  // namespace detail

}  // namespace fulcrum::io
