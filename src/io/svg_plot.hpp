#pragma once
// Self-contained SVG line charts (no script, no external fonts or styles):
// one or more panels sharing the x axis, each with ticks, labels and a legend.
// Used by `fulcrum run --plot` for energy and momentum over time; reusable for
// any time series.
#include <string>
#include <vector>

namespace fulcrum::detail {

struct PlotSeries {
    std::string label;
    std::vector<double> values;  // one per x
    std::string color;           // any SVG colour ("#1f77b4")
};

struct PlotPanel {
    std::string title;
    std::string yLabel;
    std::vector<PlotSeries> series;
};

// The SVG document. Every sample is drawn while there are at most 800 (about
// one per pixel column); longer series are reduced to a min/max envelope per
// column, so spikes survive and the file stays small. x spans the plot frame
// over the data's range; each panel's y axis spans its series' range widened
// by 5 % on each side (a constant panel: by 10 % of the value, or 1 at zero),
// so no curve runs along the frame.
std::string svgPlot(const std::string& title, const std::string& xLabel, const std::vector<double>& x,
                    const std::vector<PlotPanel>& panels);

// "Nice" tick positions (1, 2 or 5 times a power of ten) covering [lo, hi].
std::vector<double> niceTicks(double lo, double hi, int targetCount);

}  // namespace fulcrum::detail
