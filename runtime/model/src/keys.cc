// ed25519 key files (model_integrity.h): one text line, a prefix naming the kind of key, then
// the key in hex. Text, so a key can be checked and copied by eye; the prefix, so a secret key
// is never taken for a public one (or the reverse).

#include <sodium.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "tlvlink/model_integrity.h"
#include "tlvlink/regular_file.h"

namespace tlvlink {
namespace {

constexpr std::string_view kPublicPrefix = "tlvlink-ed25519-public-key ";
constexpr std::string_view kSecretPrefix = "tlvlink-ed25519-secret-key ";

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Parses "<prefix><2*N hex digits>" with an optional trailing newline into `out`.
Status parse_key(std::span<const char> text, std::string_view prefix, const char* what,
                 std::span<uint8_t> out) {
  std::string_view s(text.data(), text.size());
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.remove_suffix(1);
  TLV_ENSURE(s.substr(0, prefix.size()) == prefix, ErrorCode::kFormat,
             "not a tlvlink %s key file: it should start with '%.*s'", what,
             static_cast<int>(prefix.size() - 1), prefix.data());
  s.remove_prefix(prefix.size());
  TLV_ENSURE(s.size() == 2 * out.size(), ErrorCode::kFormat, "%s key: %zu hex digits, expected %zu",
             what, s.size(), 2 * out.size());
  for (size_t i = 0; i < out.size(); ++i) {
    const int hi = hex_digit(s[2 * i]), lo = hex_digit(s[2 * i + 1]);
    TLV_ENSURE(hi >= 0 && lo >= 0, ErrorCode::kFormat, "%s key: character %zu is not a hex digit",
               what, prefix.size() + 2 * i);
    out[i] = static_cast<uint8_t>(hi << 4 | lo);
  }
  return {};
}

}  // namespace

PublicKey public_half(const SecretKey& key) {
  PublicKey pk;
  crypto_sign_ed25519_sk_to_pk(pk.bytes.data(), key.bytes.data());
  return pk;
}

Result<PublicKey> parse_public_key(std::span<const char> text) {
  PublicKey key;
  TLV_TRY(parse_key(text, kPublicPrefix, "public", key.bytes));
  return key;
}

Result<SecretKey> parse_secret_key(std::span<const char> text) {
  SecretKey key;
  TLV_TRY(parse_key(text, kSecretPrefix, "secret", key.bytes));
  // libsodium's secret key repeats the public key after the seed: check they belong together,
  // or a damaged file would sign with one key and name another.
  std::array<uint8_t, 32> pk;
  std::array<uint8_t, 64> sk;
  crypto_sign_seed_keypair(pk.data(), sk.data(), key.bytes.data());
  const bool match = sodium_memcmp(sk.data(), key.bytes.data(), sk.size()) == 0;
  sodium_memzero(sk.data(), sk.size());
  TLV_ENSURE(match, ErrorCode::kFormat,
             "secret key: its public half does not match its seed (damaged key file)");
  return key;
}

Result<PublicKey> read_public_key_file(const char* path) {
  // A regular file only, opened non-blocking: a FIFO here must not hang a daemon's start.
  char text[256];
  auto read = RegularFile::read_head(path, std::as_writable_bytes(std::span<char>(text)));
  if (!read.ok()) return read.error().with_context("public key file");
  const size_t n = *read;
  auto key = parse_public_key(std::span<const char>(text, n));
  if (!key.ok()) return key.error().with_context("%s", path);
  return key;
}

}  // namespace tlvlink
