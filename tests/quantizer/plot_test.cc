// The sweep's SVG plot: well-formed, every point drawn, axes and legend present; tick helpers.

#include <gtest/gtest.h>

#include "tlvlink/quantize/plot.h"

namespace tlvlink::quantize {
namespace {

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

TEST(Plot, NiceStepsAndDecadeLabels) {
  EXPECT_DOUBLE_EQ(nice_step(1.2, 6), 0.2);
  EXPECT_DOUBLE_EQ(nice_step(10, 5), 2);
  EXPECT_DOUBLE_EQ(nice_step(7, 6), 2);
  EXPECT_EQ(decade_label(-3), "1e-3");
  EXPECT_EQ(decade_label(0), "1");
}

TEST(Plot, SvgHasAxesLegendAndOneMarkerPerPoint) {
  PlotSpec spec;
  spec.title = "error <vs> time";
  spec.x_label = "latency, ms";
  spec.y_label = "1 - cosine";
  spec.series = {"fp32", "int8 minmax"};
  spec.shapes = {"a.tlvm", "b.tlvm"};
  spec.fills = {"1 thread", "2 threads"};
  spec.y_floor = 1e-6;
  const std::vector<PlotPoint> points = {
      {0.9, 0.0, 0, 0, 0}, {0.6, 0.0, 0, 0, 1}, {1.0, 3e-4, 1, 1, 0}, {0.7, 3e-4, 1, 1, 1}};
  const std::string svg = error_latency_svg(points, spec);
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("error &lt;vs&gt; time"), std::string::npos);  // escaped
  EXPECT_NE(svg.find("latency, ms"), std::string::npos);
  EXPECT_NE(svg.find("1e-6"), std::string::npos);  // the floor decade is labelled
  EXPECT_NE(svg.find("1e-3"), std::string::npos);
  // 4 points + legend (2 series, 2 shapes, 2 fills) + the plot frame (a rect).
  const size_t markers = count(svg, "<circle") + count(svg, "<polygon") + count(svg, "<rect x=");
  EXPECT_EQ(markers, 4u + 6u + 1u);
  EXPECT_EQ(count(svg, "fill=\"white\" stroke="), 2u + 1u);  // hollow: 2-thread points + legend
  EXPECT_EQ(svg.find("(log scale)"), std::string::npos);

  spec.log_x = true;
  const std::vector<PlotPoint> wide = {{0.4, 1e-3, 0, 0, 0}, {300.0, 2e-3, 1, 0, 1}};
  const std::string log_svg = error_latency_svg(wide, spec);
  EXPECT_NE(log_svg.find("(log scale)"), std::string::npos);
  for (const char* tick : {">0.1<", ">1<", ">10<", ">100<", ">1000<"})
    EXPECT_NE(log_svg.find(tick), std::string::npos) << tick;
}

}  // namespace
}  // namespace tlvlink::quantize
