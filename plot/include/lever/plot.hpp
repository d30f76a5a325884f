// lever/plot.hpp: self-contained SVG charts (line, scatter, bars), so that lever's tools and the
// lesson programs can draw torque budgets, workspace maps and trajectories without Python or any
// download. The output is plain SVG 1.1 text that every browser and Debian's rsvg-convert render.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace lever::plot {

/// One data series of an x-y chart.
struct Series {
  enum class Style { kLine, kPoints };
  std::string label;  ///< legend entry ("" for none)
  std::vector<double> x, y;
  std::string color;  ///< CSS color; "" picks the next color of the palette
  Style style = Style::kLine;
  bool dashed = false;        ///< lines only
  double point_radius = 1.6;  ///< points only, in pixels
};

/// A horizontal or vertical reference line (a motor limit, a joint stop).
struct RefLine {
  enum class Axis { kHorizontal, kVertical };
  Axis axis = Axis::kHorizontal;
  double at = 0.0;
  std::string label;
  std::string color = "#888888";
};

/// An x-y chart.
struct Chart {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  std::vector<RefLine> lines;
  bool equal_aspect = false;  ///< one unit is the same length on both axes (maps, trails)
  std::optional<std::array<double, 2>> xrange, yrange;  ///< fixed ranges; default: the data's
  int width = 640, height = 400;                        ///< pixels
};

/// Grouped bars: one group per category (a joint), one bar per quantity in the group.
struct BarChart {
  struct Bar {
    std::string label;  ///< legend entry, shared by the bars of the same index across groups
    double value = 0.0;
    std::string color;  ///< "" picks the palette color of the bar's index
  };
  struct Group {
    std::string label;
    std::vector<Bar> bars;
  };
  std::string title, ylabel;
  std::vector<Group> groups;
  int width = 640, height = 400;
};

/// Several charts side by side (a row), each in its own panel.
struct Figure {
  std::string title;
  std::vector<Chart> charts;
  std::vector<BarChart> bar_charts;  ///< drawn after the charts
};

std::string to_svg(const Chart& chart);
std::string to_svg(const BarChart& chart);
std::string to_svg(const Figure& figure);

/// Write text to a file; throws std::runtime_error naming the path if it cannot.
void write_file(const std::string& path, const std::string& text);

/// "Nice" tick positions covering [lo, hi] (steps of 1, 2 or 5 times a power of ten).
std::vector<double> nice_ticks(double lo, double hi, int target_count = 6);

}  // namespace lever::plot
