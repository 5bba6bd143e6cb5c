#pragma once
// A small self-contained SVG scatter plot of error against run time for `quantize-sweep`:
// linear or log x (latency, ms), log y (error), one colour per variant, one marker shape per model,
// filled markers for the first thread count and hollow ones for the others, axes with ticks and
// labels, and a legend. Plain SVG 1.1 (no scripts, no external fonts), readable in a browser.

#include <string>
#include <vector>

namespace tlvlink::quantize {

struct PlotPoint {
  double x = 0;       // latency, ms
  double y = 0;       // error (> 0; values below PlotSpec::y_floor are drawn at the floor)
  size_t series = 0;  // colour: index into PlotSpec::series
  size_t shape = 0;   // marker: index into PlotSpec::shapes
  size_t fill = 0;    // 0 filled, else hollow: index into PlotSpec::fills
};

struct PlotSpec {
  std::string title, x_label, y_label;
  std::vector<std::string> series;  // legend: colours
  std::vector<std::string> shapes;  // legend: marker shapes
  std::vector<std::string> fills;   // legend: filled / hollow
  double y_floor = 1e-9;            // log axis floor (an exact 0 error sits here)
  bool log_x = false;               // log latency axis (ticks 1, 2, 5 x 10^k), for wide spreads
};

std::string error_latency_svg(const std::vector<PlotPoint>& points, const PlotSpec& spec);

// "1e-3" style label of a power of ten.
std::string decade_label(int exponent);
// A "nice" tick step (1, 2 or 5 x 10^k) giving about `target` ticks over `range`.
double nice_step(double range, int target);

}  // namespace tlvlink::quantize
