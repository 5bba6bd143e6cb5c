#include "tlvlink/boards/strip.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "tlvlink/atomic_file.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/daemon/model_check.h"
#include "tlvlink/model.h"
#include "tlvlink/model_integrity.h"
#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/quantize/model_sign.h"

namespace tlvlink::boards {
namespace {

// A scene names a head by its name or "kind:name" (as tlvlinkd's `heads`).
bool named(const std::vector<std::string>& names, const std::string& kind,
           const std::string& name) {
  return std::any_of(names.begin(), names.end(),
                     [&](const std::string& n) { return n == name || n == kind + ":" + name; });
}

uint64_t file_size(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? static_cast<uint64_t>(st.st_size) : 0;
}

}  // namespace

Result<StripReport> strip_model(const std::string& model_path, const daemon::Scene& scene,
                                const std::string& out_path, const std::string& secret_key_file) {
  SecretKey key;
  if (!secret_key_file.empty()) {
    TLV_ASSIGN_OR_RETURN(key, quantize::read_secret_key_file(secret_key_file));
  }
  auto loaded = Model::load_file(model_path.c_str());
  if (!loaded.ok()) return loaded.error().with_context("model %s", model_path.c_str());
  const Model& model = **loaded;
  const Metadata& md = model.metadata();
  quantize::MetadataSpec spec = quantize::metadata_spec_from(md);
  StripReport report;
  report.bytes_before = file_size(model_path);

  // Every head the scene asks for must exist.
  std::string known;
  for (const LinearHead& h : md.linear_heads)
    known += (known.empty() ? "" : ", ") + std::string("probe:") + std::string(h.name);
  for (const ZeroShotHead& h : md.zero_shot_heads)
    known += (known.empty() ? "" : ", ") + std::string("zero-shot:") + std::string(h.name);
  for (const LinearHead& h : md.press_heads)
    known += (known.empty() ? "" : ", ") + std::string("press:") + std::string(h.name);
  if (md.grasp_head.present)
    known += (known.empty() ? "" : ", ") + std::string("grasp:") + std::string(md.grasp_head.name);
  for (const std::string& want : scene.heads) {
    const bool found =
        std::any_of(
            md.linear_heads.begin(), md.linear_heads.end(),
            [&](const LinearHead& h) { return named({want}, "probe", std::string(h.name)); }) ||
        std::any_of(md.zero_shot_heads.begin(), md.zero_shot_heads.end(),
                    [&](const ZeroShotHead& h) {
                      return named({want}, "zero-shot", std::string(h.name));
                    }) ||
        std::any_of(md.press_heads.begin(), md.press_heads.end(), [&](const LinearHead& h) {
          return named({want}, "press", std::string(h.name));
        });
    TLV_ENSURE(found, ErrorCode::kInvalidArgument,
               "scene '%s' (%s) asks for head '%s', which %s does not have (it has: %s)",
               scene.name.c_str(), scene.path.c_str(), want.c_str(), model_path.c_str(),
               known.empty() ? "no heads" : known.c_str());
  }
  TLV_ENSURE(
      scene.grasp == "off" || md.grasp_head.present, ErrorCode::kInvalidArgument,
      "scene '%s' (%s) predicts grasps (grasp = \"%s\"), but %s has no grasp head (it has: %s)",
      scene.name.c_str(), scene.path.c_str(), scene.grasp.c_str(), model_path.c_str(),
      known.empty() ? "no heads" : known.c_str());

  // Keep what the scene uses.
  const std::vector<quantize::LinearHeadSpec> linear = std::move(spec.linear_heads);
  spec.linear_heads.clear();
  for (size_t i = 0; i < md.linear_heads.size(); ++i) {
    const std::string name(md.linear_heads[i].name);
    const bool keep = named(scene.heads, "probe", name);
    (keep ? report.kept : report.removed).push_back("probe:" + name);
    if (keep) spec.linear_heads.push_back(linear[i]);
  }
  std::vector<quantize::ZeroShotHeadSpec> zero_shot;
  for (size_t i = 0; i < md.zero_shot_heads.size(); ++i) {
    const std::string name(md.zero_shot_heads[i].name);
    const bool keep = named(scene.heads, "zero-shot", name);
    (keep ? report.kept : report.removed).push_back("zero-shot:" + name);
    if (keep) zero_shot.push_back(spec.zero_shot_heads[i]);
  }
  spec.zero_shot_heads = std::move(zero_shot);
  std::vector<quantize::LinearHeadSpec> press;
  for (size_t i = 0; i < md.press_heads.size(); ++i) {
    const std::string name(md.press_heads[i].name);
    const bool keep = named(scene.heads, "press", name);
    (keep ? report.kept : report.removed).push_back("press:" + name);
    if (keep) press.push_back(spec.press_heads[i]);
  }
  spec.press_heads = std::move(press);
  if (md.grasp_head.present) {
    const std::string name = "grasp:" + std::string(md.grasp_head.name);
    const bool keep = scene.grasp != "off";
    (keep ? report.kept : report.removed).push_back(name);
    if (!keep) {
      spec.has_grasp_head = false;
      spec.sensor_grasp_heads.clear();
    }
  }
  report.golden_before = md.golden.size();
  TLV_ENSURE(!md.golden.empty(), ErrorCode::kInvalidState,
             "%s has no golden pairs: a stripped model must be verifiable on the board",
             model_path.c_str());
  report.golden_after = std::min(md.golden.size(), static_cast<size_t>(scene.golden_pairs));
  for (size_t i = 0; i < report.golden_after; ++i) {
    const GoldenPair& g = md.golden[i];
    spec.golden.emplace_back(std::vector<std::byte>(g.input.begin(), g.input.end()),
                             std::vector<std::byte>(g.output.begin(), g.output.end()));
  }
  TLV_ASSIGN_OR_RETURN(quantize::ModelBuilder builder,
                       quantize::rebuild_with_metadata(model, spec));
  std::vector<std::byte> bytes = builder.finish();
  if (!secret_key_file.empty()) {
    TLV_ASSIGN_OR_RETURN(bytes, quantize::sign_model(bytes, key));
    report.signed_copy = true;
  }
  if (model.integrity().is_signed) {
    for (uint8_t b : model.integrity().key_id) {
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02x", b);
      report.source_key_id += hex;
    }
  }

  // Written beside out_path and judged as the board will (loader, golden pairs, the scene's
  // sensors and heads; the reference executor: the host has no opinion on the board's
  // kernels) before it replaces out_path.
  TLV_ASSIGN_OR_RETURN(AtomicFile file, AtomicFile::create(out_path.c_str()));
  TLV_TRY(file.write(bytes));
  const std::string toml = daemon::scene_config_toml(scene, file.temp_path(), 1, "strip check");
  auto config = daemon::parse_config(toml, scene.path + " (as a tlvlinkd configuration)");
  if (!config.ok()) return config.error();
  config->executor = "reference";
  TLV_ASSIGN_OR_RETURN(const daemon::ModelCheck check, daemon::check_model(*config));
  TLV_ENSURE(check.golden_pass, ErrorCode::kModelChecksum,
             "%s: golden pairs of the stripped copy do not hold (max error %.4g > %.4g)",
             out_path.c_str(), check.max_error, check.tolerance);
  TLV_TRY(file.commit());
  report.bytes_after = bytes.size();
  report.golden_pass = true;
  return report;
}

}  // namespace tlvlink::boards
