// Line plots on log-log axes as SVG text, written by pmcr itself (no plotting dependency): the
// convergence plots of `pmcr bench` (Err against render time, one line per method).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace pmcr {

struct PlotSeries {
    std::string label;
    std::vector<std::pair<double, double>> points;  // (x, y); points with x or y <= 0 are skipped
};

struct PlotAxes {
    std::string title;
    std::string xLabel;
    std::string yLabel;
};

// A standalone SVG document: each axis spans its data (5% wider), grid lines at 1..9 x 10^k,
// labels at decades (1-2-5 steps within less than two decades), one polyline with point
// markers per series in a fixed colour order, a legend, axis labels. Series with no plottable
// point appear in the legend only, marked "(no data)".
std::string logLogPlotSvg(const PlotAxes& axes, const std::vector<PlotSeries>& series);

// The colour the plot gives series i ("#rrggbb").
std::string plotColor(size_t i);

// Text with &, <, >, " and ' escaped for XML and HTML.
std::string escapeXml(const std::string& text);

}  // namespace pmcr
