// The position pass over JSON text; see json_locator.hpp for why it exists.
#include "io/json_locator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <unordered_set>
#include <vector>

namespace fulcrum::detail {

namespace {

// Deeper documents are not scenes; the limit keeps the recursion bounded.
constexpr int kMaxDepth = 256;

thread_local std::uint64_t bytesScanned = 0;

// Paths as errors print them: `bodies[3].shape.radius`.
void appendKey(std::string& path, std::string_view key) {
    if (!path.empty()) path += '.';
    path += key;
}
void appendIndex(std::string& path, std::size_t index) {
    path += '[';
    path += std::to_string(index);
    path += ']';
}

// Lines and columns of increasing offsets into a text, counted in one sweep.
class LineCounter {
public:
    explicit LineCounter(std::string_view text) : text_(text) {}

    // The location of byte `offset` (clamped to the text's end); offsets must
    // not decrease from one call to the next.
    TextLocation advanceTo(std::size_t offset) {
        const std::size_t end = std::min(offset, text_.size());
        if (end > pos_) bytesScanned += end - pos_;
        for (; pos_ < end; ++pos_) {
            if (text_[pos_] == '\n') {
                ++loc_.line;
                loc_.column = 1;
            } else {
                ++loc_.column;
            }
        }
        return loc_;
    }

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    TextLocation loc_{1, 1};
};

struct StopScan {};

// The keys of one object, to find a duplicate: a linear search is fastest for
// the few keys of a scene's objects, a hash set keeps a huge object (a fuzzed
// file's) linear in its size.
class KeySet {
public:
    // False when `key` is already in the set.
    bool insert(std::string key) {
        if (hashed_.empty() && list_.size() < kLinearSearchLimit) {
            if (std::find(list_.begin(), list_.end(), key) != list_.end()) return false;
            list_.push_back(std::move(key));
            return true;
        }
        if (hashed_.empty()) hashed_.insert(std::make_move_iterator(list_.begin()), std::make_move_iterator(list_.end()));
        return hashed_.insert(std::move(key)).second;
    }

private:
    static constexpr std::size_t kLinearSearchLimit = 32;
    std::vector<std::string> list_;
    std::unordered_set<std::string> hashed_;
};  // unwinds the recursion once the answer is known

class Scanner {
public:
    // Locate: the position of `target`. FindProblem: the first duplicate key
    // or overflowing number. IndexElements: where the elements of the root
    // object's arrays begin and end, in `rootArrays`.
    enum class Mode { Locate, FindProblem, IndexElements };

    Scanner(std::string_view text, Mode mode, std::string_view target) : text_(text), mode_(mode), target_(target) {}

    void run() {
        try {
            value(0);
        } catch (const StopScan&) {
        }
        bytesScanned += pos_;
    }

    std::optional<TextLocation> found;
    std::optional<JsonScanProblem> problem;
    struct Range {
        std::size_t begin, end;
    };
    struct RootArray {
        std::string key;
        std::vector<Range> elements;
    };
    std::vector<RootArray> rootArrays;

private:
    void skipWhitespace() {
        while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n' || text_[pos_] == '\r')) ++pos_;
    }

    void checkTarget(std::size_t at) {
        if (mode_ == Mode::Locate && path_ == target_) {
            found = locationOfOffset(text_, at);
            throw StopScan{};
        }
    }

    void report(std::size_t at, std::string reason) {
        problem = JsonScanProblem{path_, locationOfOffset(text_, at), std::move(reason)};
        throw StopScan{};
    }

    static void appendUtf8(std::string& out, unsigned cp) {
        if (cp < 0x80) {
            out += static_cast<char>(cp);
        } else if (cp < 0x800) {
            out += static_cast<char>(0xC0 | (cp >> 6));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            out += static_cast<char>(0xE0 | (cp >> 12));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        } else {
            out += static_cast<char>(0xF0 | (cp >> 18));
            out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
            out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (cp & 0x3F));
        }
    }

    unsigned hex4() {
        unsigned v = 0;
        for (int k = 0; k < 4 && pos_ < text_.size(); ++k, ++pos_) {
            const char c = text_[pos_];
            v <<= 4;
            if (c >= '0' && c <= '9') v |= static_cast<unsigned>(c - '0');
            else if (c >= 'a' && c <= 'f') v |= static_cast<unsigned>(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F') v |= static_cast<unsigned>(c - 'A' + 10);
        }
        return v;
    }

    // At the opening quote; returns the decoded string (keys must compare
    // equal to nlohmann's decoded keys).
    std::string string() {
        std::string out;
        ++pos_;
        while (pos_ < text_.size() && text_[pos_] != '"') {
            const char c = text_[pos_++];
            if (c != '\\') {
                out += c;
                continue;
            }
            if (pos_ >= text_.size()) break;
            const char e = text_[pos_++];
            switch (e) {
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'n': out += '\n'; break;
                case 'r': out += '\r'; break;
                case 't': out += '\t'; break;
                case 'u': {
                    unsigned cp = hex4();
                    if (cp >= 0xD800 && cp < 0xDC00 && pos_ + 1 < text_.size() && text_[pos_] == '\\' && text_[pos_ + 1] == 'u') {
                        pos_ += 2;
                        const unsigned low = hex4();
                        cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
                    }
                    appendUtf8(out, cp);
                    break;
                }
                default: out += e; break;  // \" \\ \/
            }
        }
        ++pos_;  // closing quote
        return out;
    }

    void number() {
        const std::size_t start = pos_;
        while (pos_ < text_.size()) {
            const char c = text_[pos_];
            if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E') ++pos_;
            else break;
        }
        // Only an exponent or more than 308 digits can overflow a double: the
        // conversion is skipped for the other numbers (it cost 8 % of a load).
        const std::string_view digits = text_.substr(start, pos_ - start);
        if (mode_ == Mode::FindProblem && (digits.find_first_of("eE") != std::string_view::npos || digits.size() > 300)) {
            const std::string token(digits);
            const double v = std::strtod(token.c_str(), nullptr);
            if (!std::isfinite(v)) report(start, "number " + token + " is out of range (not a finite number)");
        }
    }

    void value(int depth) {
        skipWhitespace();
        if (pos_ >= text_.size()) return;
        if (depth > kMaxDepth) {
            if (mode_ == Mode::FindProblem) report(pos_, "nested deeper than " + std::to_string(kMaxDepth) + " levels");
            throw StopScan{};
        }
        const char c = text_[pos_];
        if (c == '{') {
            object(depth);
        } else if (c == '[') {
            array(depth);
        } else if (c == '"') {
            string();
        } else if (c == '-' || (c >= '0' && c <= '9')) {
            number();
        } else {
            while (pos_ < text_.size() && text_[pos_] >= 'a' && text_[pos_] <= 'z') ++pos_;  // true, false, null
        }
    }

    void object(int depth) {
        ++pos_;
        KeySet keys;
        for (;;) {
            skipWhitespace();
            if (pos_ >= text_.size() || text_[pos_] == '}') break;
            const std::size_t keyStart = pos_;
            std::string key = string();
            const std::size_t saved = path_.size();
            appendKey(path_, key);
            if (mode_ == Mode::IndexElements && depth == 0) rootKey_ = key;
            if (mode_ == Mode::FindProblem && !keys.insert(std::move(key))) report(keyStart, "duplicate key");
            checkTarget(keyStart);
            skipWhitespace();
            ++pos_;  // ':'
            value(depth + 1);
            path_.resize(saved);
            skipWhitespace();
            if (pos_ < text_.size() && text_[pos_] == ',') ++pos_;
        }
        ++pos_;
    }

    void array(int depth) {
        ++pos_;
        std::vector<Range>* ranges = nullptr;
        if (mode_ == Mode::IndexElements && depth == 1 && rootKey_) ranges = &rootArrays.emplace_back(RootArray{*rootKey_, {}}).elements;
        for (std::size_t index = 0;; ++index) {
            skipWhitespace();
            if (pos_ >= text_.size() || text_[pos_] == ']') break;
            const std::size_t saved = path_.size();
            appendIndex(path_, index);
            checkTarget(pos_);
            const std::size_t begin = pos_;
            value(depth + 1);
            if (ranges) ranges->push_back({begin, pos_});
            path_.resize(saved);
            skipWhitespace();
            if (pos_ < text_.size() && text_[pos_] == ',') ++pos_;
        }
        ++pos_;
    }

    std::string_view text_;
    Mode mode_;
    std::string_view target_;
    std::size_t pos_ = 0;
    std::string path_;
    std::optional<std::string> rootKey_;  // IndexElements: the root member being scanned
};

}  // namespace

TextLocation locationOfOffset(std::string_view text, std::size_t offset) { return LineCounter(text).advanceTo(offset); }

std::optional<TextLocation> locateJsonPath(std::string_view text, std::string_view path) {
    Scanner scanner(text, Scanner::Mode::Locate, path);
    if (path.empty()) {
        std::size_t i = 0;
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\r')) ++i;
        return locationOfOffset(text, i);
    }
    scanner.run();
    return scanner.found;
}

JsonElementIndex::JsonElementIndex(std::string_view text) {
    Scanner scanner(text, Scanner::Mode::IndexElements, {});
    scanner.run();
    // The scan met the elements in document order: one sweep counts their lines.
    LineCounter lines(text);
    arrays_.reserve(scanner.rootArrays.size());
    for (const Scanner::RootArray& array : scanner.rootArrays) {
        Array& out = arrays_.emplace_back(Array{array.key, {}});
        out.elements.reserve(array.elements.size());
        for (const Scanner::Range& r : array.elements) {
            out.elements.push_back({lines.advanceTo(r.begin), text.substr(r.begin, r.end - r.begin)});
        }
    }
}

std::span<const JsonElement> JsonElementIndex::elements(std::string_view key) const {
    for (const Array& array : arrays_) {
        if (array.key == key) return array.elements;
    }
    return {};
}

std::optional<JsonScanProblem> findJsonProblem(std::string_view text) {
    Scanner scanner(text, Scanner::Mode::FindProblem, {});
    scanner.run();
    return scanner.problem;
}

std::uint64_t jsonBytesScanned() { return bytesScanned; }

std::string childPath(std::string_view parent, std::string_view key) {
    std::string p(parent);
    appendKey(p, key);
    return p;
}

std::string childPath(std::string_view parent, std::size_t index) {
    std::string p(parent);
    appendIndex(p, index);
    return p;
}

}  // namespace fulcrum::detail
