// Built when TLVLINK_WITH_SERIAL is OFF: listen/replay explain how to get them.

#include "common.h"
#include "record_stream.h"

namespace tlvlink::cli {
namespace {
void add_unavailable(CLI::App& app, int& exit_code, const char* name) {
  CLI::App* cmd = app.add_subcommand(
      name, "(not built: needs -DTLVLINK_WITH_PROTOCOL=ON -DTLVLINK_WITH_SERIAL=ON)");
  cmd->allow_extras();
  cmd->callback([&exit_code, name] {
    exit_code = report_error(
        name, Error(ErrorCode::kInvalidArgument,
                    "this build has no stream support: configure with -DTLVLINK_WITH_SERIAL=ON"));
  });
}
}  // namespace

void add_listen_command(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "listen");
}
Result<record::RecordReport> record_stream_images(const std::string&, int32_t,
                                                  const record::RecordOptions&,
                                                  const std::string&) {
  return Error::make(ErrorCode::kInvalidArgument,
                     "record --stream: this tlvlink was built without the stream's host side "
                     "(TLVLINK_WITH_SERIAL=OFF): it cannot read stream recordings");
}
void add_replay_command(CLI::App& app, int& exit_code) {
  add_unavailable(app, exit_code, "replay");
}

}  // namespace tlvlink::cli
