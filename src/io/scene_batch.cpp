// Scene overrides and batches from scene files (include/fulcrum/scene_batch.hpp).
#include "fulcrum/scene_batch.hpp"

#include <cctype>
#include <new>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

namespace fulcrum {

namespace {

using nlohmann::json;

struct Segment {
    enum class Kind { Key, Index, Name } kind;
    std::string text;      // Key: the key; Name: the element's name
    std::size_t index = 0;  // Index
};

[[noreturn]] void refuse(std::string_view source, const SceneOverride& o, const std::string& reason) {
    throw SceneError(std::string(source), o.path, 0, 0, reason);
}

std::vector<Segment> parsePath(std::string_view source, const SceneOverride& o) {
    const std::string& p = o.path;
    std::vector<Segment> segments;
    std::size_t i = 0;
    if (p.empty()) refuse(source, o, "empty override path");
    // Its keys become the document's keys, which must be UTF-8 to be written
    // (found by fuzz/overrides_fuzz.cpp: nlohmann's type_error escaped).
    try {
        (void)json(p).dump();
    } catch (const json::exception&) {
        refuse(source, o, "the path is not UTF-8 text");
    }
    while (i < p.size()) {
        const std::size_t keyEnd = p.find_first_of(".[]", i);
        const std::string key = p.substr(i, keyEnd == std::string::npos ? std::string::npos : keyEnd - i);
        if (key.empty()) refuse(source, o, "malformed path: a key is missing at character " + std::to_string(i + 1));
        segments.push_back({Segment::Kind::Key, key, 0});
        i = keyEnd == std::string::npos ? p.size() : keyEnd;
        while (i < p.size() && p[i] == '[') {
            const std::size_t close = p.find(']', i);
            if (close == std::string::npos) refuse(source, o, "malformed path: '[' without ']'");
            const std::string inside = p.substr(i + 1, close - i - 1);
            if (inside.empty()) refuse(source, o, "malformed path: empty []");
            bool digits = true;
            for (char c : inside) digits = digits && std::isdigit(static_cast<unsigned char>(c)) != 0;
            if (digits) {
                segments.push_back({Segment::Kind::Index, inside, std::stoul(inside)});
            } else {
                segments.push_back({Segment::Kind::Name, inside, 0});
            }
            i = close + 1;
        }
        if (i < p.size()) {
            if (p[i] != '.') refuse(source, o, std::string("malformed path: unexpected '") + p[i] + "'");
            ++i;
            if (i == p.size()) refuse(source, o, "malformed path: ends with '.'");
        }
    }
    return segments;
}

std::string kindOf(const json& v) {
    if (v.is_object()) return "an object";
    if (v.is_array()) return "an array";
    if (v.is_string()) return "a string";
    if (v.is_number()) return "a number";
    if (v.is_boolean()) return "a boolean";
    return "null";
}

void applyOne(json& root, const SceneOverride& o, std::string_view source) {
    const std::vector<Segment> segments = parsePath(source, o);
    json value;
    try {
        value = json::parse(o.value);
    } catch (const json::exception&) {
        refuse(source, o, "value is not valid JSON: " + o.value);
    }
    json* node = &root;
    std::string where = "the scene";
    for (std::size_t s = 0; s < segments.size(); ++s) {
        const Segment& seg = segments[s];
        const bool last = s + 1 == segments.size();
        if (seg.kind == Segment::Kind::Key) {
            if (!node->is_object()) refuse(source, o, where + " is " + kindOf(*node) + ", not an object with '" + seg.text + "'");
            auto it = node->find(seg.text);
            if (it == node->end()) {
                // A key the scene leaves at its default: added (the reader checks the name).
                // Objects on the way are added only where a key follows.
                if (!last && segments[s + 1].kind != Segment::Kind::Key)
                    refuse(source, o, where + " has no '" + seg.text + "'");
                node = &(*node)[seg.text];
                if (!last) *node = json::object();
            } else {
                node = &*it;
            }
            where = "'" + seg.text + "'";
        } else {
            if (!node->is_array()) refuse(source, o, where + " is " + kindOf(*node) + ", not an array");
            if (seg.kind == Segment::Kind::Index) {
                if (seg.index >= node->size())
                    refuse(source, o, "index " + std::to_string(seg.index) + " out of range: " + where + " has " +
                                          std::to_string(node->size()) + " elements");
                node = &(*node)[seg.index];
            } else {
                json* found = nullptr;
                std::string names;
                for (json& element : *node) {
                    if (!element.is_object()) continue;
                    auto name = element.find("name");
                    if (name == element.end() || !name->is_string()) continue;
                    if (name->get<std::string>() == seg.text) {
                        found = &element;
                        break;
                    }
                    names += (names.empty() ? "" : ", ") + name->get<std::string>();
                }
                if (found == nullptr)
                    refuse(source, o, "no element named '" + seg.text + "' in " + where +
                                          (names.empty() ? " (it has no named elements)" : " (names: " + names + ")"));
                node = found;
            }
            where += "[" + seg.text + "]";
        }
    }
    *node = std::move(value);
}

json parseDocument(std::string_view text, std::string_view source) {
    try {
        return json::parse(text);
    } catch (const json::exception&) {
        // The reader gives the line, column and reason of malformed JSON.
        (void)parseScene(text, source);
        throw SceneError(std::string(source), "", 0, 0, "malformed JSON");
    }
}

Scene readWithOverrides(const json& base, std::string_view baseText, std::span<const SceneOverride> overrides,
                        std::string_view source) {
    json doc = base;
    for (const SceneOverride& o : overrides) applyOne(doc, o, source);
    try {
        return parseScene(doc.dump(), source);
    } catch (const SceneError&) {
        if (overrides.empty()) throw;
        (void)parseScene(baseText, source);  // a fault of the scene itself is reported as such
        // The scene is fine alone: name the first override after which it is not.
        json partial = base;
        for (const SceneOverride& o : overrides) {
            applyOne(partial, o, source);
            try {
                (void)parseScene(partial.dump(), source);
            } catch (const SceneError& e) {
                refuse(source, o, "value " + o.value + " refused: " + e.path() + ": " + e.reason());
            }
        }
        throw;  // not reached: the last prefix is the whole list
    }
}

}  // namespace

std::string applySceneOverrides(std::string_view sceneJson, std::span<const SceneOverride> overrides,
                                std::string_view sourceName) {
    json doc = parseDocument(sceneJson, sourceName);
    for (const SceneOverride& o : overrides) applyOne(doc, o, sourceName);
    return doc.dump();
}

Scene parseSceneWithOverrides(std::string_view sceneJson, std::span<const SceneOverride> overrides,
                              std::string_view sourceName) {
    if (overrides.empty()) return parseScene(sceneJson, sourceName);
    (void)parseScene(sceneJson, sourceName);  // what only the text shows (duplicate keys) is checked on the text
    return readWithOverrides(parseDocument(sceneJson, sourceName), sceneJson, overrides, sourceName);
}

Batch makeSceneBatch(std::string_view sceneJson, std::size_t count, std::span<const SceneOverrides> perWorld,
                     const BatchDef& def, std::string_view sourceName) {
    if (!perWorld.empty() && perWorld.size() != count)
        throw Error("makeSceneBatch: " + std::to_string(perWorld.size()) + " sets of overrides for " +
                    std::to_string(count) + " worlds (give one per world, or none)");
    std::vector<World> worlds;
    try {
        worlds.reserve(count);
        if (perWorld.empty()) {
            const Scene scene = parseScene(sceneJson, sourceName);
            for (std::size_t w = 0; w < count; ++w) worlds.push_back(buildWorld(scene));
            return Batch(std::move(worlds), def);
        }
        // Every world's scene is read (and so checked) before any is built.
        (void)parseScene(sceneJson, sourceName);  // what only the text shows (duplicate keys) is checked on the text
        const json base = parseDocument(sceneJson, sourceName);
        std::vector<Scene> scenes;
        scenes.reserve(count);
        for (const SceneOverrides& overrides : perWorld) scenes.push_back(readWithOverrides(base, sceneJson, overrides, sourceName));
        for (const Scene& scene : scenes) worlds.push_back(buildWorld(scene));
        return Batch(std::move(worlds), def);
    } catch (const std::bad_alloc&) {
        // A huge count is a request, not a bug: say which, not std::bad_alloc.
        throw Error("makeSceneBatch: out of memory building " + std::to_string(count) + " worlds of " +
                    std::string(sourceName) + " (" + std::to_string(worlds.size()) + " built)");
    }
}

Batch makeSceneBatch(std::span<const std::string> scenesJson, const BatchDef& def, std::span<const std::string> sourceNames) {
    if (!sourceNames.empty() && sourceNames.size() != scenesJson.size())
        throw Error("makeSceneBatch: " + std::to_string(sourceNames.size()) + " source names for " +
                    std::to_string(scenesJson.size()) + " scenes");
    std::vector<Scene> scenes;
    scenes.reserve(scenesJson.size());
    for (std::size_t i = 0; i < scenesJson.size(); ++i)
        scenes.push_back(parseScene(scenesJson[i], sourceNames.empty() ? "scene " + std::to_string(i) : sourceNames[i]));
    std::vector<World> worlds;
    worlds.reserve(scenes.size());
    for (const Scene& scene : scenes) worlds.push_back(buildWorld(scene));
    return Batch(std::move(worlds), def);
}

}  // namespace fulcrum
