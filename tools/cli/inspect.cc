// tlvlink inspect MODEL [--json]: metadata, tensors, per-operator costs, totals (tools/inspect).

#include <cstdio>

#include "common.h"
#include "tlvlink/inspect/inspect.h"

namespace tlvlink::cli {
namespace {

struct InspectOptions {
  std::string model;
  bool json = false;
};

int run_inspect(const InspectOptions& o) {
  auto model = load_model(o.model);
  if (!model.ok()) return report_error("inspect", model.error());
  if (o.json) {
    std::printf("%s\n", inspect::inspect_json(**model).dump(2).c_str());
  } else {
    std::fputs(inspect::inspect_text(**model).c_str(), stdout);
  }
  return kExitOk;
}

}  // namespace

void add_inspect_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<InspectOptions>();
  CLI::App* cmd =
      app.add_subcommand("inspect", "Show a model's metadata, tensors, per-layer MACs and memory");
  cmd->add_option("model", o->model, "Model file (.tlvm)")->required();
  cmd->add_flag("--json", o->json, "Print machine-readable JSON instead of tables");
  cmd->footer(kExitCodeFooter);
  cmd->callback([o, &exit_code] { exit_code = run_inspect(*o); });
}

}  // namespace tlvlink::cli
