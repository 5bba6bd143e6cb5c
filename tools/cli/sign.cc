// tlvlink keygen / sign / upgrade: ed25519 keys, signed model files, and files from before the
// integrity trailer rewritten with one (quantize/writer model_sign.h does the work).

#include <cstdio>

#include "common.h"
#include "tlvlink/io/file.h"
#include "tlvlink/quantize/model_sign.h"

namespace tlvlink::cli {
namespace {

struct SignOptions {
  std::string model, key, output, key_base;
};

int run_keygen(const SignOptions& o) {
  auto keys = quantize::generate_keypair();
  if (!keys.ok()) return report_error("keygen", keys.error());
  if (Status s = quantize::write_key_files(o.key_base, *keys); !s.ok())
    return report_error("keygen", s.error());
  char id[17];
  to_hex(key_id(keys->public_key), id, sizeof id);
  std::printf("wrote %s.key (secret, mode 0600) and %s.pub (public), key id %s\n",
              o.key_base.c_str(), o.key_base.c_str(), id);
  return kExitOk;
}

// Reads MODEL, transforms its bytes, writes OUT (default: MODEL itself).
template <typename Transform>
int rewrite_file(const char* command, const SignOptions& o, Transform transform) {
  auto bytes = tools::read_file(o.model, kMaxModelBytes);
  if (!bytes.ok()) return report_error(command, bytes.error());
  auto out = transform(*bytes);
  if (!out.ok()) return report_error(command, out.error().with_context("%s", o.model.c_str()));
  const std::string& path = o.output.empty() ? o.model : o.output;
  if (Status s = tools::write_file(path, *out); !s.ok()) return report_error(command, s.error());
  return kExitOk;
}

int run_sign(const SignOptions& o) {
  auto key = quantize::read_secret_key_file(o.key);
  if (!key.ok()) return report_error("sign", key.error());
  const int rc = rewrite_file(
      "sign", o, [&](std::span<const std::byte> b) { return quantize::sign_model(b, *key); });
  if (rc != kExitOk) return rc;
  char id[17];
  to_hex(key_id(public_half(*key)), id, sizeof id);
  std::printf("signed %s with key %s\n", (o.output.empty() ? o.model : o.output).c_str(), id);
  return kExitOk;
}

int run_upgrade(const SignOptions& o) {
  const int rc = rewrite_file(
      "upgrade", o, [](std::span<const std::byte> b) { return quantize::upgrade_model(b); });
  if (rc == kExitOk) {
    std::printf(
        "wrote %s: same graph, constants and metadata, with the integrity trailer and "
        "golden head outputs\n",
        (o.output.empty() ? o.model : o.output).c_str());
  }
  return rc;
}

}  // namespace

void add_sign_commands(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<SignOptions>();
  CLI::App* keygen = app.add_subcommand(
      "keygen", "Make an ed25519 key pair for signing models: BASE.key (secret, 0600), BASE.pub");
  keygen->add_option("-o,--output", o->key_base, "Key file base name (never overwritten)")
      ->required();
  keygen->footer(kExitCodeFooter);
  keygen->callback([o, &exit_code] { exit_code = run_keygen(*o); });

  CLI::App* sign = app.add_subcommand(
      "sign", "Sign a model (ed25519 over its BLAKE2b-256 hash) after validating it fully");
  sign->add_option("model", o->model, "Model file (.tlvm)")->required();
  sign->add_option("--key,-k", o->key, "Secret key file (tlvlink keygen)")->required();
  sign->add_option("-o,--output", o->output, "Output model file (default: sign in place)");
  sign->footer(kExitCodeFooter);
  sign->callback([o, &exit_code] { exit_code = run_sign(*o); });

  CLI::App* upgrade = app.add_subcommand(
      "upgrade",
      "Rewrite a model written before the integrity trailer (its old checksum is "
      "checked first): same graph and weights, whole-file hash, golden head outputs");
  upgrade->add_option("model", o->model, "Model file (.tlvm)")->required();
  upgrade->add_option("-o,--output", o->output, "Output model file")->required();
  upgrade->footer(kExitCodeFooter);
  upgrade->callback([o, &exit_code] { exit_code = run_upgrade(*o); });
}

}  // namespace tlvlink::cli
