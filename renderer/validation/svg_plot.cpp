#include "renderer/validation/svg_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <pugixml.hpp>
#include <sstream>
#include <utility>

namespace kiln {
namespace {

using Attributes = std::initializer_list<std::pair<const char*, std::string>>;

pugi::xml_node add(pugi::xml_node parent, const char* name, Attributes attributes,
                   const std::string& text = "") {
    pugi::xml_node node = parent.append_child(name);
    for (const auto& [key, value] : attributes) node.append_attribute(key) = value.c_str();
    if (!text.empty()) node.text() = text.c_str();
    return node;
}

std::string n(double v) { return fmt::format("{:.1f}", v); }

// Plot area in pixels and the decades it spans.
struct Frame {
    static constexpr double W = 640, H = 420, L = 70, R = 170, T = 40, B = 50;
    double x0 = 0, x1 = 1, y0 = 0, y1 = 1;  // log10 ranges
    double px(double lx) const { return L + (lx - x0) / (x1 - x0) * (W - L - R); }
    double py(double ly) const { return H - B - (ly - y0) / (y1 - y0) * (H - T - B); }
};

Frame frameOf(const std::vector<PlotSeries>& series) {
    Frame f;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const PlotSeries& s : series)
        for (size_t i = 0; i < s.x.size(); ++i)
            if (s.x[i] > 0 && s.y[i] > 0) {
                x0 = std::min(x0, std::log10(s.x[i])), x1 = std::max(x1, std::log10(s.x[i]));
                y0 = std::min(y0, std::log10(s.y[i])), y1 = std::max(y1, std::log10(s.y[i]));
            }
    if (x0 > x1) return f;
    f.x0 = std::floor(x0), f.x1 = std::ceil(x1 + 1e-9);
    f.y0 = std::floor(y0), f.y1 = std::ceil(y1 + 1e-9);
    return f;
}

void addAxes(pugi::xml_node svg, const Frame& f, const std::string& xLabel,
             const std::string& yLabel) {
    for (double d = f.x0; d <= f.x1 + 1e-9; d += 1) {
        add(svg, "line",
            {{"x1", n(f.px(d))},
             {"y1", n(f.T)},
             {"x2", n(f.px(d))},
             {"y2", n(f.H - f.B)},
             {"stroke", "#ddd"}});
        add(svg, "text", {{"x", n(f.px(d))}, {"y", n(f.H - f.B + 16)}, {"text-anchor", "middle"}},
            fmt::format("1e{}", int(d)));
    }
    for (double d = f.y0; d <= f.y1 + 1e-9; d += 1) {
        add(svg, "line",
            {{"x1", n(f.L)},
             {"y1", n(f.py(d))},
             {"x2", n(f.W - f.R)},
             {"y2", n(f.py(d))},
             {"stroke", "#ddd"}});
        add(svg, "text", {{"x", n(f.L - 6)}, {"y", n(f.py(d) + 4)}, {"text-anchor", "end"}},
            fmt::format("1e{}", int(d)));
    }
    double mid = (f.T + f.H - f.B) / 2;
    add(svg, "text",
        {{"x", n((f.L + f.W - f.R) / 2)}, {"y", n(f.H - 12)}, {"text-anchor", "middle"}}, xLabel);
    add(svg, "text",
        {{"x", "16"},
         {"y", n(mid)},
         {"transform", fmt::format("rotate(-90 16 {})", n(mid))},
         {"text-anchor", "middle"}},
        yLabel);
}

void addSeries(pugi::xml_node svg, const Frame& f, const PlotSeries& s, int k) {
    static const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                    "#9467bd", "#8c564b", "#e377c2", "#17becf"};
    std::string c = colours[k % 8], points;
    for (size_t i = 0; i < s.x.size(); ++i) {
        if (!(s.x[i] > 0 && s.y[i] > 0)) continue;
        double x = f.px(std::log10(s.x[i])), y = f.py(std::log10(s.y[i]));
        points += n(x) + "," + n(y) + " ";
        add(svg, "circle", {{"cx", n(x)}, {"cy", n(y)}, {"r", "2.5"}, {"fill", c}});
    }
    add(svg, "polyline",
        {{"fill", "none"}, {"stroke", c}, {"stroke-width", "1.5"}, {"points", points}});
    double y = 50 + 18 * k;
    add(svg, "line",
        {{"x1", n(f.W - f.R + 10)},
         {"y1", n(y)},
         {"x2", n(f.W - f.R + 30)},
         {"y2", n(y)},
         {"stroke", c},
         {"stroke-width", "2"}});
    add(svg, "text", {{"x", n(f.W - f.R + 35)}, {"y", n(y + 4)}}, s.name);
}

}  // namespace

std::string svgLogLogPlot(const std::string& title, const std::string& xLabel,
                          const std::string& yLabel, const std::vector<PlotSeries>& series,
                          bool slopeMinusOne) {
    Frame f = frameOf(series);
    pugi::xml_document doc;
    pugi::xml_node svg = add(doc, "svg",
                             {{"xmlns", "http://www.w3.org/2000/svg"},
                              {"width", n(f.W)},
                              {"height", n(f.H)},
                              {"font-family", "sans-serif"},
                              {"font-size", "12"}});
    add(svg, "rect", {{"width", "100%"}, {"height", "100%"}, {"fill", "white"}});
    add(svg, "text", {{"x", n(f.L)}, {"y", "22"}, {"font-size", "14"}}, title);
    addAxes(svg, f, xLabel, yLabel);
    int k = 0;
    for (const PlotSeries& s : series) addSeries(svg, f, s, k++);
    if (slopeMinusOne && !series.empty() && !series[0].x.empty()) {
        // Through the first series' first point, slope -1: error halves when time doubles.
        double lx = std::log10(series[0].x[0]), ly = std::log10(series[0].y[0]);
        add(svg, "line",
            {{"x1", n(f.px(lx))},
             {"y1", n(f.py(ly))},
             {"x2", n(f.px(f.x1))},
             {"y2", n(f.py(ly - (f.x1 - lx)))},
             {"stroke", "#888"},
             {"stroke-dasharray", "6 4"}});
        add(svg, "text", {{"x", n(f.W - f.R + 35)}, {"y", n(54 + 18 * k)}, {"fill", "#888"}},
            "slope -1");
    }
    std::ostringstream os;
    doc.save(os, "  ", pugi::format_default | pugi::format_no_declaration);
    return os.str();
}

}  // namespace kiln
