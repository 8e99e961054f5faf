#pragma once
// Reads back what detail::svgPlot drew, so tests compare the drawn points with
// the data instead of only finding a <polyline>: each panel's frame (the
// unfilled <rect>) and its polylines' points, in document order.
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace fulcrum::testing {

struct SvgPoint {
    double x = 0, y = 0;
};

struct SvgPanel {
    double left = 0, top = 0, width = 0, height = 0;  // the plot frame
    std::vector<std::vector<SvgPoint>> polylines;
};

// The value of attribute `name` in the element starting at `from` (up to its '>').
inline std::string svgAttribute(const std::string& svg, std::size_t from, const std::string& name) {
    const std::size_t end = svg.find('>', from);
    const std::size_t at = svg.find(" " + name + "=\"", from);
    if (at == std::string::npos || at > end) return {};
    const std::size_t begin = at + name.size() + 3;
    return svg.substr(begin, svg.find('"', begin) - begin);
}

inline std::vector<SvgPoint> svgPoints(const std::string& text) {
    std::vector<SvgPoint> points;
    const char* p = text.c_str();
    while (*p != '\0') {
        char* end = nullptr;
        const double x = std::strtod(p, &end);
        if (end == p || *end != ',') break;
        p = end + 1;
        const double y = std::strtod(p, &end);
        if (end == p) break;
        points.push_back({x, y});
        p = end;
        while (*p == ' ') ++p;
    }
    return points;
}

// One entry per <g> panel.
inline std::vector<SvgPanel> svgPanels(const std::string& svg) {
    std::vector<SvgPanel> panels;
    for (std::size_t g = svg.find("<g>"); g != std::string::npos; g = svg.find("<g>", g + 1)) {
        const std::size_t gEnd = svg.find("</g>", g);
        SvgPanel panel;
        for (std::size_t r = svg.find("<rect ", g); r < gEnd; r = svg.find("<rect ", r + 1)) {
            if (svgAttribute(svg, r, "fill") != "none") continue;
            panel.left = std::stod(svgAttribute(svg, r, "x"));
            panel.top = std::stod(svgAttribute(svg, r, "y"));
            panel.width = std::stod(svgAttribute(svg, r, "width"));
            panel.height = std::stod(svgAttribute(svg, r, "height"));
        }
        for (std::size_t l = svg.find("<polyline", g); l < gEnd; l = svg.find("<polyline", l + 1)) {
            panel.polylines.push_back(svgPoints(svgAttribute(svg, l, "points")));
        }
        panels.push_back(std::move(panel));
    }
    return panels;
}

// Where svg_plot.hpp says a sample lands: x spans the frame over [xLo, xHi];
// y over the panel's value range [lo, hi] widened by 5 % on each side, or for
// a constant panel (lo == hi) by 10 % of |value| (1 when the value is 0).
struct SvgMapping {
    SvgPanel frame;
    double xLo, xHi, yLo, yHi;
    SvgMapping(const SvgPanel& panel, double x0, double x1, double lo, double hi) : frame(panel), xLo(x0), xHi(x1) {
        if (hi - lo <= 1e-12 * std::max(1.0, std::fabs(hi))) {
            const double pad = std::max(1e-9, std::fabs(hi) * 0.1 + (hi == 0 ? 1 : 0));
            yLo = lo - pad;
            yHi = hi + pad;
        } else {
            yLo = lo - 0.05 * (hi - lo);
            yHi = hi + 0.05 * (hi - lo);
        }
    }
    SvgPoint operator()(double x, double v) const {
        return {frame.left + (x - xLo) / (xHi - xLo) * frame.width, frame.top + frame.height - (v - yLo) / (yHi - yLo) * frame.height};
    }
};

}  // namespace fulcrum::testing
