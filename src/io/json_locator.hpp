#pragma once
// A light second pass over JSON text that knows where each value sits.
// nlohmann-json (3.11) builds the document but keeps no source positions, so
// when a value is found wrong we re-scan the text to turn its document path
// (`bodies[3].shape.radius`) into a line and column. The same scan finds what
// nlohmann accepts silently or reports without a position: duplicate keys
// (nlohmann keeps the last) and numbers too large for a double (1e999).
// The scanner assumes syntactically valid JSON (nlohmann checked it first).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace fulcrum::detail {

struct TextLocation {
    int line = 0;    // 1-based
    int column = 0;  // 1-based, in bytes
};

// Line and column of byte `offset` of `text`.
TextLocation locationOfOffset(std::string_view text, std::size_t offset);

// Location of the value at `path` ("" is the root; object members are located
// at their key). nullopt when the path does not occur.
std::optional<TextLocation> locateJsonPath(std::string_view text, std::string_view path);

// Where the elements of the root object's arrays sit (`bodies[3]`,
// `joints[0]`: the elements a Scene keeps a SceneLocation for) and their
// text, all found in one pass. Locating each with locateJsonPath instead
// re-scans the text up to it, quadratic in the element count (issue 27: 24 s
// for a 10,000-body file); deeper paths are only needed for an error, once
// per document, and locateJsonPath serves those. With each element's text the
// scene parser reads one element at a time instead of the whole document at
// once (a million bodies' document tree took a gigabyte).
struct JsonElement {
    TextLocation where;     // locateJsonPath(text, childPath(key, index))
    std::string_view text;  // the element's value, from its first to its last character
};

class JsonElementIndex {
public:
    explicit JsonElementIndex(std::string_view text);

    // The elements of the root's array `key`, in order; none when the root
    // has no such array.
    std::span<const JsonElement> elements(std::string_view key) const;

private:
    struct Array {
        std::string key;
        std::vector<JsonElement> elements;
    };
    std::vector<Array> arrays_;
};

// The first problem of a document nlohmann parses without complaint (or
// without a position): a duplicate key, or a number that overflows a double.
struct JsonScanProblem {
    std::string path;
    TextLocation where;
    std::string reason;
};
std::optional<JsonScanProblem> findJsonProblem(std::string_view text);

// Bytes of text that the scans above (and locationOfOffset) have read on this
// thread so far. Loading a scene must read its text a bounded number of times
// whatever its size; tests/io/scene_load_scaling_test.cpp checks that with it.
std::uint64_t jsonBytesScanned();

// Joins a path and a member key / array index the way errors print them.
std::string childPath(std::string_view parent, std::string_view key);
std::string childPath(std::string_view parent, std::size_t index);

}  // namespace fulcrum::detail
