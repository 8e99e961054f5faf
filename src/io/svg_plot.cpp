// SVG line charts, written directly (see svg_plot.hpp).
#include "io/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "io/markup_escape.hpp"

namespace fulcrum::detail {

namespace {

constexpr double kWidth = 900;
constexpr double kPanelHeight = 260;
constexpr double kLeft = 90, kRight = 170, kTop = 50, kGap = 60, kBottom = 60;
constexpr std::size_t kMaxColumns = 800;  // envelope resolution (about one per pixel of plot width)

std::string fmt(double v, const char* format = "%.2f") {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

// Tick label with as many decimals as the tick step needs.
std::string tickLabel(double v, double step) {
    if (v == 0) return "0";
    const double mag = std::fabs(v);
    if (mag >= 1e5 || mag < 1e-3) return fmt(v, "%.3g");
    const int decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
    char format[16];
    std::snprintf(format, sizeof format, "%%.%df", std::min(decimals, 6));
    return fmt(v, format);
}

struct Range {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    void grow(double v) {
        if (!std::isfinite(v)) return;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    bool empty() const { return !(lo <= hi); }
};

// Pads a degenerate or empty range so the axis has extent.
Range padded(Range r) {
    if (r.empty()) return {0, 1};
    if (r.hi - r.lo <= 1e-12 * std::max(1.0, std::fabs(r.hi))) {
        const double pad = std::max(1e-9, std::fabs(r.hi) * 0.1 + (r.hi == 0 ? 1 : 0));
        return {r.lo - pad, r.hi + pad};
    }
    const double pad = (r.hi - r.lo) * 0.05;
    return {r.lo - pad, r.hi + pad};
}

}  // namespace

std::vector<double> niceTicks(double lo, double hi, int targetCount) {
    std::vector<double> ticks;
    if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || targetCount < 1) return ticks;
    const double raw = (hi - lo) / targetCount;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    const double frac = raw / power;
    const double step = (frac <= 1 ? 1 : frac <= 2 ? 2 : frac <= 5 ? 5 : 10) * power;
    for (double t = std::ceil(lo / step) * step; t <= hi + step * 1e-9; t += step) {
        ticks.push_back(std::fabs(t) < step * 1e-9 ? 0.0 : t);
        if (ticks.size() > 100) break;
    }
    return ticks;
}

std::string svgPlot(const std::string& title, const std::string& xLabel, const std::vector<double>& x,
                    const std::vector<PlotPanel>& panels) {
    const double plotW = kWidth - kLeft - kRight;
    const double height = kTop + static_cast<double>(panels.size()) * (kPanelHeight + kGap) - kGap + kBottom;
    std::string svg;
    svg.reserve(64 * 1024);
    svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(kWidth, "%.0f") + "\" height=\"" + fmt(height, "%.0f") +
           "\" viewBox=\"0 0 " + fmt(kWidth, "%.0f") + " " + fmt(height, "%.0f") + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + fmt(kWidth / 2) + "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">" + escapeMarkup(title) + "</text>\n";

    Range xr;
    for (double v : x) xr.grow(v);
    if (xr.empty() || xr.hi <= xr.lo) xr = padded(xr);
    const auto xPix = [&](double v) { return kLeft + (v - xr.lo) / (xr.hi - xr.lo) * plotW; };
    const std::vector<double> xTicks = niceTicks(xr.lo, xr.hi, 8);
    const double xStep = xTicks.size() > 1 ? xTicks[1] - xTicks[0] : 1;

    for (std::size_t p = 0; p < panels.size(); ++p) {
        const PlotPanel& panel = panels[p];
        const double top = kTop + static_cast<double>(p) * (kPanelHeight + kGap);
        const double bottom = top + kPanelHeight;
        Range yr;
        for (const PlotSeries& s : panel.series) {
            for (double v : s.values) yr.grow(v);
        }
        yr = padded(yr);
        const auto yPix = [&](double v) { return bottom - (v - yr.lo) / (yr.hi - yr.lo) * kPanelHeight; };

        svg += "<g>\n<text x=\"" + fmt(kLeft) + "\" y=\"" + fmt(top - 8) + "\" font-size=\"13\">" + escapeMarkup(panel.title) + "</text>\n";
        // Grid and ticks.
        const std::vector<double> yTicks = niceTicks(yr.lo, yr.hi, 6);
        const double yStep = yTicks.size() > 1 ? yTicks[1] - yTicks[0] : 1;
        for (double t : yTicks) {
            const double y = yPix(t);
            svg += "<line x1=\"" + fmt(kLeft) + "\" y1=\"" + fmt(y) + "\" x2=\"" + fmt(kLeft + plotW) + "\" y2=\"" + fmt(y) +
                   "\" stroke=\"#e6e6e6\"/>\n";
            svg += "<line x1=\"" + fmt(kLeft - 5) + "\" y1=\"" + fmt(y) + "\" x2=\"" + fmt(kLeft) + "\" y2=\"" + fmt(y) + "\" stroke=\"black\"/>\n";
            svg += "<text x=\"" + fmt(kLeft - 8) + "\" y=\"" + fmt(y + 4) + "\" text-anchor=\"end\">" + tickLabel(t, yStep) + "</text>\n";
        }
        for (double t : xTicks) {
            const double xp = xPix(t);
            svg += "<line x1=\"" + fmt(xp) + "\" y1=\"" + fmt(top) + "\" x2=\"" + fmt(xp) + "\" y2=\"" + fmt(bottom) + "\" stroke=\"#e6e6e6\"/>\n";
            svg += "<line x1=\"" + fmt(xp) + "\" y1=\"" + fmt(bottom) + "\" x2=\"" + fmt(xp) + "\" y2=\"" + fmt(bottom + 5) + "\" stroke=\"black\"/>\n";
            svg += "<text x=\"" + fmt(xp) + "\" y=\"" + fmt(bottom + 18) + "\" text-anchor=\"middle\">" + tickLabel(t, xStep) + "</text>\n";
        }
        svg += "<rect x=\"" + fmt(kLeft) + "\" y=\"" + fmt(top) + "\" width=\"" + fmt(plotW) + "\" height=\"" + fmt(kPanelHeight) +
               "\" fill=\"none\" stroke=\"black\"/>\n";
        svg += "<text transform=\"translate(" + fmt(kLeft - 62) + "," + fmt(top + kPanelHeight / 2) +
               ") rotate(-90)\" text-anchor=\"middle\">" + escapeMarkup(panel.yLabel) + "</text>\n";
        if (p + 1 == panels.size()) {
            svg += "<text x=\"" + fmt(kLeft + plotW / 2) + "\" y=\"" + fmt(bottom + 40) + "\" text-anchor=\"middle\">" + escapeMarkup(xLabel) +
                   "</text>\n";
        }

        // Series: a min/max envelope per column when there are more points than columns.
        for (std::size_t si = 0; si < panel.series.size(); ++si) {
            const PlotSeries& s = panel.series[si];
            const std::size_t n = std::min(s.values.size(), x.size());
            std::string points;
            const std::size_t columns = std::max<std::size_t>(1, std::min(n, kMaxColumns));
            for (std::size_t c = 0; c < columns && n > 0; ++c) {
                const std::size_t begin = c * n / columns, end = std::max(begin + 1, (c + 1) * n / columns);
                std::size_t iMin = begin, iMax = begin;
                for (std::size_t i = begin; i < end; ++i) {
                    if (s.values[i] < s.values[iMin]) iMin = i;
                    if (s.values[i] > s.values[iMax]) iMax = i;
                }
                // The column's extremes in time order; one point when they are the
                // same sample (a column of one sample, or a constant stretch).
                const std::size_t first = std::min(iMin, iMax), second = std::max(iMin, iMax);
                const auto draw = [&](std::size_t i) {
                    if (std::isfinite(s.values[i])) points += fmt(xPix(x[i])) + "," + fmt(yPix(s.values[i])) + " ";
                };
                draw(first);
                if (second != first) draw(second);
            }
            svg += "<polyline fill=\"none\" stroke=\"" + escapeMarkup(s.color) + "\" stroke-width=\"1.5\" points=\"" + points + "\"/>\n";
            const double ly = top + 14 + static_cast<double>(si) * 18;
            const double lx = kLeft + plotW + 15;
            svg += "<line x1=\"" + fmt(lx) + "\" y1=\"" + fmt(ly - 4) + "\" x2=\"" + fmt(lx + 20) + "\" y2=\"" + fmt(ly - 4) + "\" stroke=\"" +
                   escapeMarkup(s.color) + "\" stroke-width=\"2\"/>\n";
            svg += "<text x=\"" + fmt(lx + 26) + "\" y=\"" + fmt(ly) + "\">" + escapeMarkup(s.label) + "</text>\n";
        }
        svg += "</g>\n";
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace fulcrum::detail
