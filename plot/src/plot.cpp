// SVG charts. Each chart is drawn into a <g> at an offset, so a Figure can place several.
#include <lever/plot.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace lever::plot {

namespace {

// Colors that stay apart for the color-blind (Okabe-Ito).
const char* const kPalette[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                "#E69F00", "#56B4E9", "#F0E442", "#000000"};
constexpr int kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

std::string escape(const std::string& s) {
  std::string out;
  for (const char ch : s) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", x);
  return buf;
}

// A tick label with as few digits as the step needs.
std::string tick_label(double x, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::abs(x) < 0.5 * step ? 0.0 : x);
  return buf;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
  // pad a little, and open up a degenerate range
  void finish() {
    if (empty()) {
      lo = 0;
      hi = 1;
    }
    if (hi - lo < 1e-12 * std::max(1.0, std::abs(hi))) {
      const double pad = std::max(1e-3, 0.1 * std::abs(hi));
      lo -= pad;
      hi += pad;
    } else {
      const double pad = 0.04 * (hi - lo);
      lo -= pad;
      hi += pad;
    }
  }
};

// The plotting area of a chart and its data-to-pixel mapping.
struct Frame {
  double left, top, width, height;
  Range x, y;
  double px(double v) const { return left + (v - x.lo) / (x.hi - x.lo) * width; }
  double py(double v) const { return top + height - (v - y.lo) / (y.hi - y.lo) * height; }
};

void text(std::ostringstream& svg, double x, double y, const std::string& s, const char* anchor,
          int size, const char* extra = "") {
  svg << "<text x=\"" << num(x) << "\" y=\"" << num(y) << "\" text-anchor=\"" << anchor
      << "\" font-size=\"" << size << "\"" << extra << ">" << escape(s) << "</text>\n";
}

void axes(std::ostringstream& svg, const Frame& f, const std::string& xlabel,
          const std::string& ylabel) {
  svg << "<rect x=\"" << num(f.left) << "\" y=\"" << num(f.top) << "\" width=\"" << num(f.width)
      << "\" height=\"" << num(f.height) << "\" fill=\"none\" stroke=\"#444\"/>\n";
  const std::vector<double> xt = nice_ticks(f.x.lo, f.x.hi);
  const std::vector<double> yt = nice_ticks(f.y.lo, f.y.hi);
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1.0;
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  for (const double t : xt) {
    const double x = f.px(t);
    svg << "<line x1=\"" << num(x) << "\" y1=\"" << num(f.top) << "\" x2=\"" << num(x) << "\" y2=\""
        << num(f.top + f.height) << "\" stroke=\"#e4e4e4\"/>\n";
    text(svg, x, f.top + f.height + 16, tick_label(t, xstep), "middle", 11);
  }
  for (const double t : yt) {
    const double y = f.py(t);
    svg << "<line x1=\"" << num(f.left) << "\" y1=\"" << num(y) << "\" x2=\""
        << num(f.left + f.width) << "\" y2=\"" << num(y) << "\" stroke=\"#e4e4e4\"/>\n";
    text(svg, f.left - 6, y + 4, tick_label(t, ystep), "end", 11);
  }
  text(svg, f.left + f.width / 2, f.top + f.height + 36, xlabel, "middle", 13);
  const double ly = f.top + f.height / 2, lx = f.left - 48;
  svg << "<text x=\"" << num(lx) << "\" y=\"" << num(ly) << "\" text-anchor=\"middle\" "
      << "font-size=\"13\" transform=\"rotate(-90 " << num(lx) << " " << num(ly) << ")\">"
      << escape(ylabel) << "</text>\n";
}

void legend(std::ostringstream& svg, const Frame& f,
            const std::vector<std::pair<std::string, std::string>>& entries,
            const std::vector<bool>& dashed) {
  double y = f.top + 14;
  for (size_t i = 0; i < entries.size(); ++i) {
    if (entries[i].first.empty()) continue;
    const double x = f.left + f.width - 150;
    svg << "<line x1=\"" << num(x) << "\" y1=\"" << num(y - 4) << "\" x2=\"" << num(x + 18)
        << "\" y2=\"" << num(y - 4) << "\" stroke=\"" << entries[i].second
        << "\" stroke-width=\"3\"" << (dashed[i] ? " stroke-dasharray=\"6 3\"" : "") << "/>\n";
    text(svg, x + 24, y, entries[i].first, "start", 11);
    y += 16;
  }
}

// Draw a chart into svg at (x0, y0).
void draw_chart(std::ostringstream& svg, const Chart& c, double x0, double y0) {
  Frame f{x0 + 70,
          y0 + (c.title.empty() ? 14 : 34),
          c.width - 90.0,
          c.height - (c.title.empty() ? 14.0 : 34.0) - 52,
          {},
          {}};
  for (const Series& s : c.series) {
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      f.x.add(s.x[i]);
      f.y.add(s.y[i]);
    }
  }
  for (const RefLine& l : c.lines) (l.axis == RefLine::Axis::kHorizontal ? f.y : f.x).add(l.at);
  f.x.finish();
  f.y.finish();
  if (c.xrange) f.x = Range{(*c.xrange)[0], (*c.xrange)[1]};
  if (c.yrange) f.y = Range{(*c.yrange)[0], (*c.yrange)[1]};
  if (c.equal_aspect) {
    // widen whichever range is short, so one unit has one length
    const double sx = (f.x.hi - f.x.lo) / f.width, sy = (f.y.hi - f.y.lo) / f.height;
    if (sx > sy) {
      const double mid = 0.5 * (f.y.lo + f.y.hi), half = 0.5 * sx * f.height;
      f.y = Range{mid - half, mid + half};
    } else {
      const double mid = 0.5 * (f.x.lo + f.x.hi), half = 0.5 * sy * f.width;
      f.x = Range{mid - half, mid + half};
    }
  }
  if (!c.title.empty())
    text(svg, x0 + c.width / 2.0, y0 + 20, c.title, "middle", 15, " font-weight=\"bold\"");
  axes(svg, f, c.xlabel, c.ylabel);

  const std::string clip =
      "clip" + std::to_string(static_cast<long>(x0)) + "_" + std::to_string(static_cast<long>(y0));
  svg << "<clipPath id=\"" << clip << "\"><rect x=\"" << num(f.left) << "\" y=\"" << num(f.top)
      << "\" width=\"" << num(f.width) << "\" height=\"" << num(f.height) << "\"/></clipPath>\n";
  svg << "<g clip-path=\"url(#" << clip << ")\">\n";
  for (const RefLine& l : c.lines) {
    const bool h = l.axis == RefLine::Axis::kHorizontal;
    const double a = h ? f.py(l.at) : f.px(l.at);
    svg << "<line x1=\"" << num(h ? f.left : a) << "\" y1=\"" << num(h ? a : f.top) << "\" x2=\""
        << num(h ? f.left + f.width : a) << "\" y2=\"" << num(h ? a : f.top + f.height)
        << "\" stroke=\"" << l.color << "\" stroke-width=\"1.5\" stroke-dasharray=\"4 4\"/>\n";
    if (!l.label.empty()) {
      text(svg, h ? f.left + 6 : a + 4, h ? a - 5 : f.top + 14, l.label, "start", 11,
           (" fill=\"" + l.color + "\"").c_str());
    }
  }
  std::vector<std::pair<std::string, std::string>> entries;
  std::vector<bool> dashed;
  int next_color = 0;
  for (const Series& s : c.series) {
    const std::string color = s.color.empty() ? kPalette[next_color++ % kPaletteSize] : s.color;
    entries.emplace_back(s.label, color);
    dashed.push_back(s.dashed);
    const size_t n = std::min(s.x.size(), s.y.size());
    if (s.style == Series::Style::kPoints) {
      svg << "<g fill=\"" << color << "\">\n";
      for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        svg << "<circle cx=\"" << num(f.px(s.x[i])) << "\" cy=\"" << num(f.py(s.y[i])) << "\" r=\""
            << num(s.point_radius) << "\"/>\n";
      }
      svg << "</g>\n";
    } else {
      svg << "<polyline fill=\"none\" stroke=\"" << color << "\" stroke-width=\"2\""
          << (s.dashed ? " stroke-dasharray=\"6 3\"" : "") << " points=\"";
      for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        svg << num(f.px(s.x[i])) << "," << num(f.py(s.y[i])) << " ";
      }
      svg << "\"/>\n";
    }
  }
  svg << "</g>\n";
  legend(svg, f, entries, dashed);
}

void draw_bars(std::ostringstream& svg, const BarChart& c, double x0, double y0) {
  Frame f{x0 + 70,
          y0 + (c.title.empty() ? 14 : 34),
          c.width - 90.0,
          c.height - (c.title.empty() ? 14.0 : 34.0) - 52,
          {},
          {}};
  f.y.add(0.0);
  size_t per_group = 0;
  for (const auto& g : c.groups) {
    per_group = std::max(per_group, g.bars.size());
    for (const auto& b : g.bars) f.y.add(b.value);
  }
  f.y.finish();
  f.y.lo = std::min(0.0, f.y.lo);
  f.x = Range{0.0, static_cast<double>(std::max<size_t>(1, c.groups.size()))};
  if (!c.title.empty())
    text(svg, x0 + c.width / 2.0, y0 + 20, c.title, "middle", 15, " font-weight=\"bold\"");
  // y axis with grid; x axis carries the group labels instead of numbers
  const std::vector<double> yt = nice_ticks(f.y.lo, f.y.hi);
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1.0;
  svg << "<rect x=\"" << num(f.left) << "\" y=\"" << num(f.top) << "\" width=\"" << num(f.width)
      << "\" height=\"" << num(f.height) << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (const double t : yt) {
    const double y = f.py(t);
    svg << "<line x1=\"" << num(f.left) << "\" y1=\"" << num(y) << "\" x2=\""
        << num(f.left + f.width) << "\" y2=\"" << num(y) << "\" stroke=\"#e4e4e4\"/>\n";
    text(svg, f.left - 6, y + 4, tick_label(t, ystep), "end", 11);
  }
  const double ly = f.top + f.height / 2, lx = f.left - 48;
  svg << "<text x=\"" << num(lx) << "\" y=\"" << num(ly) << "\" text-anchor=\"middle\" "
      << "font-size=\"13\" transform=\"rotate(-90 " << num(lx) << " " << num(ly) << ")\">"
      << escape(c.ylabel) << "</text>\n";
  const double group_width = f.width / std::max<size_t>(1, c.groups.size());
  const double bar_width = 0.8 * group_width / std::max<size_t>(1, per_group);
  std::vector<std::pair<std::string, std::string>> entries(per_group);
  for (size_t g = 0; g < c.groups.size(); ++g) {
    const double gx = f.left + g * group_width + 0.1 * group_width;
    for (size_t k = 0; k < c.groups[g].bars.size(); ++k) {
      const auto& b = c.groups[g].bars[k];
      const std::string color = b.color.empty() ? kPalette[k % kPaletteSize] : b.color;
      if (entries[k].first.empty()) entries[k] = {b.label, color};
      const double y1 = f.py(std::max(0.0, b.value)), y2 = f.py(std::min(0.0, b.value));
      svg << "<rect x=\"" << num(gx + k * bar_width) << "\" y=\"" << num(y1) << "\" width=\""
          << num(0.92 * bar_width) << "\" height=\"" << num(y2 - y1) << "\" fill=\"" << color
          << "\"/>\n";
      char value[32];
      std::snprintf(value, sizeof value, "%.3g", b.value);
      text(svg, gx + (k + 0.46) * bar_width, y1 - 4, value, "middle", 10);
    }
    text(svg, gx + 0.4 * group_width, f.top + f.height + 18, c.groups[g].label, "middle", 12);
  }
  legend(svg, f, entries, std::vector<bool>(entries.size(), false));
}

std::string document(double width, double height, const std::string& body) {
  std::ostringstream svg;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << num(width)
      << "\" height=\"" << num(height) << "\" viewBox=\"0 0 " << num(width) << " " << num(height)
      << "\" font-family=\"DejaVu Sans, Arial, sans-serif\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << body << "</svg>\n";
  return svg.str();
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int target_count) {
  std::vector<double> ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo) || target_count < 1) return ticks;
  const double raw = (hi - lo) / target_count;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (const double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step) ticks.push_back(t);
  return ticks;
}

std::string to_svg(const Chart& chart) {
  std::ostringstream body;
  draw_chart(body, chart, 0, 0);
  return document(chart.width, chart.height, body.str());
}

std::string to_svg(const BarChart& chart) {
  std::ostringstream body;
  draw_bars(body, chart, 0, 0);
  return document(chart.width, chart.height, body.str());
}

std::string to_svg(const Figure& figure) {
  std::ostringstream body;
  const double top = figure.title.empty() ? 0.0 : 36.0;
  double x = 0, height = 0;
  for (const Chart& c : figure.charts) {
    draw_chart(body, c, x, top);
    x += c.width;
    height = std::max(height, static_cast<double>(c.height));
  }
  for (const BarChart& c : figure.bar_charts) {
    draw_bars(body, c, x, top);
    x += c.width;
    height = std::max(height, static_cast<double>(c.height));
  }
  std::ostringstream head;
  if (!figure.title.empty()) {
    text(head, x / 2, 24, figure.title, "middle", 17, " font-weight=\"bold\"");
  }
  return document(std::max(x, 1.0), height + top, head.str() + body.str());
}

void write_file(const std::string& path, const std::string& text_out) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot open '" + path + "' for writing");
  out << text_out;
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace lever::plot
