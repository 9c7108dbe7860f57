// A log-log line plot as SVG, built as an XML document (pugixml), so titles and names with &, < or
// quotes stay valid XML.
#pragma once

#include <string>
#include <vector>

namespace kiln {

struct PlotSeries {
    std::string name;
    std::vector<double> x, y;
};

// One polyline per series (points with x, y > 0), decade grid lines, a legend, and optionally a
// dashed reference line of slope -1 through the first series' first point.
std::string svgLogLogPlot(const std::string& title, const std::string& xLabel,
                          const std::string& yLabel, const std::vector<PlotSeries>& series,
                          bool slopeMinusOne);

}  // namespace kiln
