#pragma once
// Opening a file the user named as input (a scene, a snapshot). Only regular
// files are read: a directory fails in the middle of a read, and a device or a
// FIFO (/dev/zero, a named pipe) never ends or blocks forever, so they are
// refused by their kind before a byte is read.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fulcrum::detail {

// Why `path` cannot be read as an input file, e.g. "is a directory, not a
// regular file"; nullopt for a regular file (or a symlink to one) and for a
// path that does not exist (opening it reports that).
std::optional<std::string> notARegularFile(const std::filesystem::path& path);

// Reads a regular file whole. `what` names the content in messages ("scene
// file", "snapshot"). Throws fulcrum::Error "<path>: <reason>" for a file that
// is not regular, cannot be opened or fails while being read; never lets a
// stream exception escape.
std::vector<std::uint8_t> readInputFile(const std::filesystem::path& path, const std::string& what);

// The first `count` bytes (fewer if the file is shorter), with the same checks:
// a format's magic can be checked before reading the rest.
std::vector<std::uint8_t> readInputFilePrefix(const std::filesystem::path& path, const std::string& what, std::size_t count);

}  // namespace fulcrum::detail
