// Input files (see input_file.hpp).
#include "world/input_file.hpp"

#include <algorithm>
#include <fstream>
#include <limits>

#include "fulcrum/error.hpp"

namespace fulcrum::detail {

std::optional<std::string> notARegularFile(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);  // follows symlinks
    switch (status.type()) {
        case fs::file_type::regular:
        case fs::file_type::not_found:
        case fs::file_type::none:
        case fs::file_type::unknown: return std::nullopt;  // opening it says what is wrong
        case fs::file_type::directory: return "is a directory, not a regular file";
        case fs::file_type::character: return "is a character device, not a regular file";
        case fs::file_type::block: return "is a block device, not a regular file";
        case fs::file_type::fifo: return "is a FIFO (named pipe), not a regular file";
        case fs::file_type::socket: return "is a socket, not a regular file";
        default: return "is not a regular file";
    }
}

namespace {

std::vector<std::uint8_t> read(const std::filesystem::path& path, const std::string& what, std::size_t limit) {
    if (const auto reason = notARegularFile(path)) throw Error(path.string() + ": " + *reason + " (expected a " + what + ")");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path.string() + ": cannot open the " + what + " for reading");
    std::vector<std::uint8_t> bytes;
    // Chunks, not istreambuf_iterator: a read error then sets badbit instead of throwing.
    constexpr std::size_t kChunk = 1 << 16;
    while (bytes.size() < limit && in) {
        const std::size_t at = bytes.size();
        const std::size_t want = std::min(kChunk, limit - at);
        bytes.resize(at + want);
        in.read(reinterpret_cast<char*>(bytes.data() + at), static_cast<std::streamsize>(want));
        bytes.resize(at + static_cast<std::size_t>(in.gcount()));
    }
    if (in.bad()) throw Error(path.string() + ": error while reading the " + what);
    return bytes;
}

}  // namespace

std::vector<std::uint8_t> readInputFile(const std::filesystem::path& path, const std::string& what) {
    return read(path, what, std::numeric_limits<std::size_t>::max());
}

std::vector<std::uint8_t> readInputFilePrefix(const std::filesystem::path& path, const std::string& what, std::size_t count) {
    return read(path, what, count);
}

}  // namespace fulcrum::detail
