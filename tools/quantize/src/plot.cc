// SVG scatter plot of error vs latency (see quantize_plot.h).

#include "tlvlink/quantize/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tlvlink::quantize {
namespace {

constexpr double kWidth = 960, kHeight = 600;
constexpr double kLeft = 90, kRight = 290, kTop = 60, kBottom = 70;  // plot area margins
// Colour-blind-friendly palette (Okabe-Ito, then greys).
constexpr const char* kColours[] = {"#000000", "#E69F00", "#56B4E9", "#009E73", "#D55E00",
                                    "#0072B2", "#CC79A7", "#F0E442", "#999999", "#666666"};

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", v);
  return text;
}

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

const char* colour(size_t i) { return kColours[i % (sizeof(kColours) / sizeof(kColours[0]))]; }

// A marker of shape `shape` centred at (x, y).
std::string marker(size_t shape, double x, double y, const char* fill, const char* stroke) {
  const double r = 6;
  const std::string style =
      std::string(" fill=\"") + fill + "\" stroke=\"" + stroke + "\" stroke-width=\"1.8\"/>";
  switch (shape % 5) {
    case 0:
      return "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"" + num(r) + "\"" + style;
    case 1:
      return "<rect x=\"" + num(x - r) + "\" y=\"" + num(y - r) + "\" width=\"" + num(2 * r) +
             "\" height=\"" + num(2 * r) + "\"" + style;
    case 2:
      return "<polygon points=\"" + num(x) + "," + num(y - r * 1.2) + " " + num(x - r * 1.1) + "," +
             num(y + r * 0.8) + " " + num(x + r * 1.1) + "," + num(y + r * 0.8) + "\"" + style;
    case 3:
      return "<polygon points=\"" + num(x) + "," + num(y - r * 1.3) + " " + num(x + r) + "," +
             num(y) + " " + num(x) + "," + num(y + r * 1.3) + " " + num(x - r) + "," + num(y) +
             "\"" + style;
    default:
      return "<polygon points=\"" + num(x - r) + "," + num(y - r) + " " + num(x + r) + "," +
             num(y + r) + " " + num(x) + "," + num(y) + " " + num(x + r) + "," + num(y - r) + " " +
             num(x - r) + "," + num(y + r) + " " + num(x) + "," + num(y) + "\"" + style;
  }
}

std::string text(double x, double y, const std::string& s, const char* extra = "") {
  return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\"" + extra + ">" + escape(s) + "</text>\n";
}

}  // namespace

std::string decade_label(int exponent) {
  if (exponent == 0) return "1";
  return "1e" + std::to_string(exponent);
}

double nice_step(double range, int target) {
  if (!(range > 0)) return 1;
  const double raw = range / std::max(target, 1);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

std::string error_latency_svg(const std::vector<PlotPoint>& points, const PlotSpec& spec) {
  const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
  double xmin = 0, xmax = 0, ymin = 1, ymax = spec.y_floor;
  bool first = true;
  for (const PlotPoint& p : points) {
    xmin = first ? p.x : std::min(xmin, p.x);
    xmax = std::max(xmax, p.x);
    first = false;
    const double y = std::max(p.y, spec.y_floor);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
  const bool log_x = spec.log_x && xmin > 0;
  // Linear: 0 .. a multiple of a nice step. Log: whole decades around the data.
  const double xstep = nice_step(xmax > 0 ? xmax : 1, 6);
  const double xhi = log_x ? std::pow(10.0, std::ceil(std::log10(xmax)))
                           : std::max(xstep, std::ceil(xmax * 1.05 / xstep) * xstep);
  const double xlo = log_x ? std::pow(10.0, std::floor(std::log10(xmin))) : 0.0;
  int dlo = static_cast<int>(std::floor(std::log10(ymin))),
      dhi = static_cast<int>(std::ceil(std::log10(ymax)));
  if (dhi <= dlo) dhi = dlo + 1;
  auto sx = [&](double x) {
    if (log_x)
      return kLeft + pw * (std::log10(x) - std::log10(xlo)) / (std::log10(xhi) - std::log10(xlo));
    return kLeft + pw * x / xhi;
  };
  auto sy = [&](double y) {
    const double l = std::log10(std::max(y, spec.y_floor));
    return kTop + ph * (1.0 - (l - dlo) / (dhi - dlo));
  };
  std::vector<double> xticks;
  if (log_x) {
    for (double d = xlo; d < xhi * 1.001; d *= 10)
      for (double m : {1.0, 2.0, 5.0})
        if (m * d <= xhi * 1.001) xticks.push_back(m * d);
  } else {
    for (double x = 0; x <= xhi + xstep / 2; x += xstep) xticks.push_back(x);
  }

  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
      "width=\"" +
      num(kWidth) + "\" height=\"" + num(kHeight) + "\" viewBox=\"0 0 " + num(kWidth) + " " +
      num(kHeight) + "\" font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"13\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += text(kWidth / 2 - kRight / 2 + kLeft / 2, 30, spec.title,
            " text-anchor=\"middle\" font-size=\"17\" font-weight=\"bold\"");
  // Grid and ticks.
  for (double x : xticks) {
    s += "<line x1=\"" + num(sx(x)) + "\" y1=\"" + num(kTop) + "\" x2=\"" + num(sx(x)) +
         "\" y2=\"" + num(kTop + ph) + "\" stroke=\"#dddddd\"/>\n";
    char label[32];
    std::snprintf(label, sizeof(label), "%g", x);
    s += text(sx(x), kTop + ph + 20, label, " text-anchor=\"middle\"");
  }
  for (int d = dlo; d <= dhi; ++d) {
    const double y = sy(std::pow(10.0, d));
    s += "<line x1=\"" + num(kLeft) + "\" y1=\"" + num(y) + "\" x2=\"" + num(kLeft + pw) +
         "\" y2=\"" + num(y) + "\" stroke=\"#dddddd\"/>\n";
    s += text(kLeft - 8, y + 4, decade_label(d), " text-anchor=\"end\"");
  }
  s += "<rect x=\"" + num(kLeft) + "\" y=\"" + num(kTop) + "\" width=\"" + num(pw) +
       "\" height=\"" + num(ph) + "\" fill=\"none\" stroke=\"black\"/>\n";
  s += text(kLeft + pw / 2, kHeight - 22, spec.x_label + (log_x ? " (log scale)" : ""),
            " text-anchor=\"middle\"");
  s += "<text x=\"22\" y=\"" + num(kTop + ph / 2) +
       "\" text-anchor=\"middle\" transform=\"rotate(-90 22 " + num(kTop + ph / 2) + ")\">" +
       escape(spec.y_label) + "</text>\n";
  if (ymin <= spec.y_floor)
    s += text(kLeft + 6, sy(spec.y_floor) - 6,
              "(at the floor: error " + decade_label(dlo) + " or below)",
              " font-size=\"11\" fill=\"#555555\"");
  // Points (hollow ones last so they stay visible on top of filled ones).
  for (int pass = 0; pass < 2; ++pass) {
    for (const PlotPoint& p : points) {
      if ((p.fill == 0) != (pass == 0)) continue;
      s += marker(p.shape, sx(p.x), sy(p.y), p.fill == 0 ? colour(p.series) : "white",
                  colour(p.series)) +
           "\n";
    }
  }
  // Legend.
  double ly = kTop + 10;
  const double lx = kLeft + pw + 24;
  s += text(lx, ly, "variant (colour)", " font-weight=\"bold\"");
  for (size_t i = 0; i < spec.series.size(); ++i) {
    ly += 20;
    s += marker(0, lx + 7, ly - 4, colour(i), colour(i)) + "\n" + text(lx + 20, ly, spec.series[i]);
  }
  ly += 30;
  s += text(lx, ly, "model (shape)", " font-weight=\"bold\"");
  for (size_t i = 0; i < spec.shapes.size(); ++i) {
    ly += 20;
    s += marker(i, lx + 7, ly - 4, "#777777", "#777777") + "\n" + text(lx + 20, ly, spec.shapes[i]);
  }
  ly += 30;
  s += text(lx, ly, "threads (fill)", " font-weight=\"bold\"");
  for (size_t i = 0; i < spec.fills.size(); ++i) {
    ly += 20;
    s += marker(0, lx + 7, ly - 4, i == 0 ? "#777777" : "white", "#777777") + "\n" +
         text(lx + 20, ly, spec.fills[i]);
  }
  s += "</svg>\n";
  return s;
}

}  // namespace tlvlink::quantize
