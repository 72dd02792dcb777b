#include "bench/plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>

namespace pmcr {

namespace {

// Plot geometry in SVG user units.
constexpr double kWidth = 640.0, kHeight = 420.0;
constexpr double kLeft = 80.0, kRight = 20.0, kTop = 40.0, kBottom = 55.0;
constexpr double kPlotWidth = kWidth - kLeft - kRight, kPlotHeight = kHeight - kTop - kBottom;

std::string num(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.2f", v);
    return buffer;
}

std::string tickLabel(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%g", value);
    return buffer;
}

// The log10 range shown for values in [minValue, maxValue]: theirs, 5% wider on each side (half
// a decade each side for a single value).
std::pair<double, double> logRange(double minValue, double maxValue) {
    if (!(minValue > 0.0) || !std::isfinite(maxValue))
        return {0.0, 1.0};
    const double lo = std::log10(minValue), hi = std::log10(maxValue);
    const double pad = hi > lo ? 0.05 * (hi - lo) : 0.5;
    return {lo - pad, hi + pad};
}

// Tick values within [lo, hi] (log10): m * 10^d for m in `mantissas`.
std::vector<double> ticks(double lo, double hi, std::initializer_list<int> mantissas) {
    std::vector<double> values;
    for (int d = int(std::floor(lo)); d <= int(std::ceil(hi)); ++d)
        for (int m : mantissas) {
            const double v = m * std::pow(10.0, d);
            const double l = std::log10(v);
            if (l >= lo - 1e-9 && l <= hi + 1e-9)
                values.push_back(v);
        }
    return values;
}

// Labelled ticks: decades, or 1-2-5 steps when fewer than two decades are in range.
std::vector<double> labelledTicks(double lo, double hi) {
    std::vector<double> values = ticks(lo, hi, {1});
    if (values.size() < 2)
        values = ticks(lo, hi, {1, 2, 5});
    return values;
}

}  // namespace

std::string escapeXml(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&#39;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::string plotColor(size_t i) {
    // Ten distinguishable hues (the "category10" palette of d3 and matplotlib).
    static const std::array<const char*, 10> colors = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728",
                                                       "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                                       "#bcbd22", "#17becf"};
    return colors[i % colors.size()];
}

std::string logLogPlotSvg(const PlotAxes& axes, const std::vector<PlotSeries>& series) {
    double minX = std::numeric_limits<double>::infinity(), maxX = 0.0;
    double minY = minX, maxY = 0.0;
    auto plottable = [](const std::pair<double, double>& p) {
        return p.first > 0.0 && p.second > 0.0 && std::isfinite(p.first) && std::isfinite(p.second);
    };
    for (const auto& s : series)
        for (const auto& p : s.points)
            if (plottable(p)) {
                minX = std::min(minX, p.first);
                maxX = std::max(maxX, p.first);
                minY = std::min(minY, p.second);
                maxY = std::max(maxY, p.second);
            }
    const auto [x0, x1] = logRange(minX, maxX);
    const auto [y0, y1] = logRange(minY, maxY);
    auto px = [&, x0 = x0, x1 = x1](double x) {
        return kLeft + (std::log10(x) - x0) / (x1 - x0) * kPlotWidth;
    };
    auto py = [&, y0 = y0, y1 = y1](double y) {
        return kTop + kPlotHeight - (std::log10(y) - y0) / (y1 - y0) * kPlotHeight;
    };

    std::string svg;
    svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(kWidth) + "\" height=\"" +
           num(kHeight) + "\" viewBox=\"0 0 " + num(kWidth) + " " + num(kHeight) +
           "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + num(kWidth / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" +
           escapeXml(axes.title) + "</text>\n";

    // Grid: decades darker than 2..9 within them; labels at decades (or 1-2-5 steps).
    const std::initializer_list<int> all = {1, 2, 3, 4, 5, 6, 7, 8, 9};
    for (double v : ticks(x0, x1, all)) {
        const bool decade = std::abs(std::log10(v) - std::round(std::log10(v))) < 1e-9;
        svg += "<line x1=\"" + num(px(v)) + "\" y1=\"" + num(kTop) + "\" x2=\"" + num(px(v)) +
               "\" y2=\"" + num(kTop + kPlotHeight) + "\" stroke=\"" +
               (decade ? "#bbbbbb" : "#eeeeee") + "\"/>\n";
    }
    for (double v : labelledTicks(x0, x1))
        svg += "<text x=\"" + num(px(v)) + "\" y=\"" + num(kTop + kPlotHeight + 16) +
               "\" text-anchor=\"middle\">" + tickLabel(v) + "</text>\n";
    for (double v : ticks(y0, y1, all)) {
        const bool decade = std::abs(std::log10(v) - std::round(std::log10(v))) < 1e-9;
        svg += "<line x1=\"" + num(kLeft) + "\" y1=\"" + num(py(v)) + "\" x2=\"" +
               num(kLeft + kPlotWidth) + "\" y2=\"" + num(py(v)) + "\" stroke=\"" +
               (decade ? "#bbbbbb" : "#eeeeee") + "\"/>\n";
    }
    for (double v : labelledTicks(y0, y1))
        svg += "<text x=\"" + num(kLeft - 6) + "\" y=\"" + num(py(v) + 4) +
               "\" text-anchor=\"end\">" + tickLabel(v) + "</text>\n";
    svg += "<rect x=\"" + num(kLeft) + "\" y=\"" + num(kTop) + "\" width=\"" + num(kPlotWidth) +
           "\" height=\"" + num(kPlotHeight) + "\" fill=\"none\" stroke=\"black\"/>\n";
    svg += "<text x=\"" + num(kLeft + kPlotWidth / 2) + "\" y=\"" + num(kHeight - 12) +
           "\" text-anchor=\"middle\">" + escapeXml(axes.xLabel) + "</text>\n";
    svg += "<text transform=\"translate(18," + num(kTop + kPlotHeight / 2) +
           ") rotate(-90)\" text-anchor=\"middle\">" + escapeXml(axes.yLabel) + "</text>\n";

    // One polyline with markers per series.
    for (size_t i = 0; i < series.size(); ++i) {
        std::string points;
        std::string markers;
        for (const auto& p : series[i].points) {
            if (!plottable(p))
                continue;
            const std::string xy = num(px(p.first)) + "," + num(py(p.second));
            points += (points.empty() ? "" : " ") + xy;
            markers += "<circle cx=\"" + num(px(p.first)) + "\" cy=\"" + num(py(p.second)) +
                       "\" r=\"2.5\" fill=\"" + plotColor(i) + "\"/>\n";
        }
        if (points.empty())
            continue;
        svg += "<polyline fill=\"none\" stroke=\"" + plotColor(i) +
               "\" stroke-width=\"1.8\" points=\"" + points + "\"/>\n" + markers;
    }

    // Legend, top right inside the plot.
    const double legendX = kLeft + kPlotWidth - 190, legendY = kTop + 10;
    svg += "<rect x=\"" + num(legendX - 8) + "\" y=\"" + num(legendY - 6) +
           "\" width=\"188\" height=\"" + num(18.0 * double(series.size()) + 8) +
           "\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999999\"/>\n";
    for (size_t i = 0; i < series.size(); ++i) {
        const double y = legendY + 18.0 * double(i) + 6;
        const bool empty =
            std::none_of(series[i].points.begin(), series[i].points.end(), plottable);
        svg += "<line x1=\"" + num(legendX) + "\" y1=\"" + num(y) + "\" x2=\"" + num(legendX + 24) +
               "\" y2=\"" + num(y) + "\" stroke=\"" + plotColor(i) + "\" stroke-width=\"2\"/>\n";
        svg += "<text x=\"" + num(legendX + 30) + "\" y=\"" + num(y + 4) + "\">" +
               escapeXml(series[i].label) + (empty ? " (no data)" : "") + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace pmcr
