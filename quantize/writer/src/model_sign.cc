// Re-writing, upgrading and signing whole model files (model_sign.h).

#include "tlvlink/quantize/model_sign.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "tlvlink/quantize/model_copy.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::quantize {
namespace {

// Writes `text` to a new file (O_EXCL: never replaces one) with `mode`.
Status write_new_file(const std::string& path, const std::string& text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  TLV_ENSURE(fd >= 0, ErrorCode::kIo, "cannot create key file '%s': %s", path.c_str(),
             errno == EEXIST ? "it exists (keys are never overwritten)" : std::strerror(errno));
  // The umask may have widened nothing but may have narrowed; state the mode exactly.
  const bool ok = ::fchmod(fd, mode) == 0 &&
                  ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
                  ::fsync(fd) == 0;
  const int err = errno;
  ::close(fd);
  if (!ok) ::unlink(path.c_str());
  TLV_ENSURE(ok, ErrorCode::kIo, "writing key file '%s': %s", path.c_str(), std::strerror(err));
  return {};
}

std::string hex_line(const char* prefix, std::span<const uint8_t> bytes) {
  std::string hex(2 * bytes.size() + 1, '\0');
  to_hex(bytes, hex.data(), hex.size());
  hex.pop_back();
  return std::string(prefix) + hex + "\n";
}

}  // namespace

Result<std::vector<std::byte>> rewrite_model(const Model& model) {
  // created_utc, producer and settings are copied: the rewrite is the same model, not a new one.
  TLV_ASSIGN_OR_RETURN(ModelBuilder b,
                       rebuild_with_metadata(model, metadata_spec_from(model.metadata())));
  return b.finish();
}

Result<std::vector<std::byte>> upgrade_model(std::span<const std::byte> file) {
  TLV_ASSIGN_OR_RETURN(auto model, Model::load(file, {.accept_legacy = true}));
  return rewrite_model(*model);
}

Result<std::vector<std::byte>> sign_model(std::span<const std::byte> file, const SecretKey& key) {
  // Never sign what the loader would refuse: a signature vouches for a valid, intact model.
  TLV_ASSIGN_OR_RETURN(auto model, Model::load(file));
  return seal_model(file.first(model->integrity().body_size), &key);
}

Result<KeyPair> generate_keypair() {
  TLV_ENSURE(sodium_init() >= 0, ErrorCode::kBackend, "libsodium failed to initialise");
  KeyPair k;
  crypto_sign_keypair(k.public_key.bytes.data(), k.secret.bytes.data());
  return k;
}

std::string format_public_key(const PublicKey& key) {
  return hex_line("tlvlink-ed25519-public-key ", key.bytes);
}

std::string format_secret_key(const SecretKey& key) {
  return hex_line("tlvlink-ed25519-secret-key ", key.bytes);
}

Status write_key_files(const std::string& base, const KeyPair& keys) {
  TLV_TRY(write_new_file(base + ".key", format_secret_key(keys.secret), 0600));
  if (Status s = write_new_file(base + ".pub", format_public_key(keys.public_key), 0644); !s.ok()) {
    ::unlink((base + ".key").c_str());  // a secret without its public half is of no use
    return s;
  }
  return {};
}

Result<SecretKey> read_secret_key_file(const std::string& path) {
  char text[512];
  auto read = RegularFile::read_head(path.c_str(), std::as_writable_bytes(std::span<char>(text)));
  if (!read.ok()) return read.error().with_context("secret key file");
  const size_t n = *read;
  auto key = parse_secret_key(std::span<const char>(text, n));
  sodium_memzero(text, sizeof text);
  if (!key.ok()) return key.error().with_context("%s", path.c_str());
  return key;
}

}  // namespace tlvlink::quantize
