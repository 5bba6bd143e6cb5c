// The extreme set written to disk and the invalid parameter sets checked (sets.h).

#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "tlvlink/io/file.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/sim/extreme.h"
#include "tlvlink/sim/sets.h"

namespace tlvlink::sim {
namespace {

nlohmann::ordered_json contact_json(const ContactState& c) {
  return {{"in_contact", c.in_contact},
          {"force_n", c.force_n},
          {"press_mm", c.press_mm},
          {"kappa", c.kappa},
          {"contact_area_mm2", c.contact_area_mm2},
          {"slip_ratio", c.slip_ratio},
          {"gross_slip", c.gross_slip},
          {"markers_deviating", c.markers_deviating}};
}

}  // namespace

Result<ExtremeSetSummary> write_extreme_set(const std::string& dir, uint64_t seed) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  TLV_ENSURE(!ec, ErrorCode::kIo, "cannot create directory '%s': %s", dir.c_str(),
             ec.message().c_str());
  ExtremeSetSummary out;
  std::string lines;
  for (const ExtremeCase& c : extreme_cases()) {
    const std::string name(c.name);
    auto renderer = Renderer::create(c.sensor, seed);
    if (!renderer.ok()) return renderer.error().with_context("%s", name.c_str());
    Frame frame;
    if (Status s = (*renderer)->render(c.scene, c.options, seed, frame); !s.ok())
      return s.error().with_context("%s", name.c_str());
    tools::Image image{frame.width, frame.height, 3, frame.rgb};
    TLV_TRY(tools::write_pnm((std::filesystem::path(dir) / (name + ".ppm")).string(), image));
    const auto [lo, hi] = std::minmax_element(frame.rgb.begin(), frame.rgb.end());
    nlohmann::ordered_json j = {{"name", name},
                                {"what", std::string(c.what)},
                                {"sensor", std::string(c.sensor.name)},
                                {"height", frame.height},
                                {"width", frame.width},
                                {"min", frame.rgb.empty() ? 0 : *lo},
                                {"max", frame.rgb.empty() ? 0 : *hi},
                                {"contact", contact_json(frame.state)}};
    lines += j.dump() + "\n";
    ++out.rendered;
  }
  const std::string index = (std::filesystem::path(dir) / "extreme.jsonl").string();
  TLV_TRY(
      tools::write_file(index, std::as_bytes(std::span<const char>(lines.data(), lines.size()))));
  for (const InvalidCase& c : invalid_parameter_cases()) {
    ++out.invalid_total;
    const Status s = validate_all(c.sensor, c.scene, c.options);
    if (s.ok() || std::string(s.error().message()).find(std::string(c.field)) == std::string::npos)
      out.unrejected.push_back(c.name + " was not rejected naming '" + std::string(c.field) + "'");
  }
  return out;
}

}  // namespace tlvlink::sim
