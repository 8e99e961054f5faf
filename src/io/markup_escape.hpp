#pragma once
// Text placed in HTML or SVG (element text or a quoted attribute value).
#include <string>
#include <string_view>

namespace fulcrum::detail {

// & < > " as entities: safe in element text and in double-quoted attributes.
inline std::string escapeMarkup(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

}  // namespace fulcrum::detail
