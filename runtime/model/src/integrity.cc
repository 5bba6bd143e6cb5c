// The integrity trailer (model_integrity.h; byte layout in runtime/README.md "Integrity trailer").
//
//   offset  size  field
//        0     4  magic "TLVH"
//        4     2  version (little-endian), 1
//        6     2  flags (little-endian): bit 0 = signed; other bits 0
//        8     8  key id of the signer (zero when unsigned)
//       16    32  BLAKE2b-256( file[0 : size-112] || trailer[0:16] )
//       48    64  ed25519 signature of kSignedPrefix || hash (zero when unsigned)

#include <sodium.h>

#include <cstring>

#include "tlvlink/model_integrity.h"

namespace tlvlink {
namespace {

constexpr size_t kHeaderBytes = 16;
constexpr size_t kHashOffset = 16;
constexpr size_t kSignatureOffset = 48;
// Domain separation: a signature over a model hash can never be replayed as one over anything
// else signed with the same key.
constexpr char kSignedPrefix[] = "tlvlink model signature v1";

bool sodium_ready() {
  static const bool ready = sodium_init() >= 0;  // idempotent and thread-safe in libsodium
  return ready;
}

ModelHash hash_of(std::span<const std::byte> body, const uint8_t* header) {
  crypto_generichash_state state;
  crypto_generichash_init(&state, nullptr, 0, crypto_generichash_BYTES);
  crypto_generichash_update(&state, reinterpret_cast<const uint8_t*>(body.data()), body.size());
  crypto_generichash_update(&state, header, kHeaderBytes);
  ModelHash h;
  crypto_generichash_final(&state, h.data(), h.size());
  return h;
}

std::array<uint8_t, sizeof(kSignedPrefix) - 1 + 32> signed_message(const ModelHash& hash) {
  std::array<uint8_t, sizeof(kSignedPrefix) - 1 + 32> m{};
  std::memcpy(m.data(), kSignedPrefix, sizeof(kSignedPrefix) - 1);
  std::memcpy(m.data() + sizeof(kSignedPrefix) - 1, hash.data(), hash.size());
  return m;
}

bool all_zero(std::span<const uint8_t> v) {
  for (uint8_t b : v) {
    if (b != 0) return false;
  }
  return true;
}

}  // namespace

void to_hex(std::span<const uint8_t> bytes, char* out, size_t out_size) {
  static constexpr char kDigits[] = "0123456789abcdef";
  size_t n = 0;
  for (size_t i = 0; i < bytes.size() && n + 2 < out_size; ++i) {
    out[n++] = kDigits[bytes[i] >> 4];
    out[n++] = kDigits[bytes[i] & 15];
  }
  if (out_size > 0) out[n] = '\0';
}

KeyId key_id(const PublicKey& key) {
  std::array<uint8_t, 32> h;
  crypto_generichash(h.data(), h.size(), key.bytes.data(), key.bytes.size(), nullptr, 0);
  KeyId id;
  std::memcpy(id.data(), h.data(), id.size());
  return id;
}

bool has_integrity_trailer(std::span<const std::byte> file) {
  return file.size() > kTrailerBytes &&
         std::memcmp(file.data() + file.size() - kTrailerBytes, kTrailerMagic, 4) == 0;
}

Result<ModelIntegrity> read_integrity(std::span<const std::byte> file, bool check_hash) {
  TLV_ENSURE(sodium_ready(), ErrorCode::kBackend, "libsodium failed to initialise");
  TLV_ENSURE(has_integrity_trailer(file), ErrorCode::kModelChecksum,
             "no integrity trailer: rewrite it with `tlvlink upgrade MODEL -o NEW` (a file "
             "from before the whole-file hash, whose checksum covered only the constants)");
  const auto* t = reinterpret_cast<const uint8_t*>(file.data()) + file.size() - kTrailerBytes;
  const uint16_t version = static_cast<uint16_t>(t[4] | t[5] << 8);
  const uint16_t flags = static_cast<uint16_t>(t[6] | t[7] << 8);
  TLV_ENSURE(version == kTrailerVersion, ErrorCode::kModelChecksum,
             "integrity trailer version %u, this runtime reads version %u", version,
             kTrailerVersion);
  TLV_ENSURE((flags & ~kTrailerSigned) == 0, ErrorCode::kModelChecksum,
             "integrity trailer flags 0x%04x: unknown bits set (only bit 0, signed, is defined)",
             flags);
  ModelIntegrity m;
  m.body_size = file.size() - kTrailerBytes;
  m.is_signed = (flags & kTrailerSigned) != 0;
  std::memcpy(m.key_id.data(), t + 8, m.key_id.size());
  std::memcpy(m.hash.data(), t + kHashOffset, m.hash.size());
  std::memcpy(m.signature.data(), t + kSignatureOffset, m.signature.size());
  TLV_ENSURE(m.is_signed || (all_zero(m.key_id) && all_zero(m.signature)),
             ErrorCode::kModelChecksum,
             "integrity trailer: the file is unsigned but its key id / signature bytes are not "
             "zero: the trailer was modified or corrupted");
  if (check_hash) {
    const ModelHash actual = hash_of(file.first(m.body_size), t);
    if (sodium_memcmp(actual.data(), m.hash.data(), actual.size()) != 0) {
      char want[65], got[65];
      to_hex(m.hash, want, sizeof want);
      to_hex(actual, got, sizeof got);
      return Error::make(ErrorCode::kModelChecksum,
                         "integrity check failed: BLAKE2b-256 of the file is %.16s..., its "
                         "trailer records %.16s...: modified or corrupted after it was written",
                         got, want);
    }
  }
  return m;
}

Status check_signature(const ModelIntegrity& m, const PublicKey& key) {
  TLV_ENSURE(sodium_ready(), ErrorCode::kBackend, "libsodium failed to initialise");
  char want[17], have[17];
  to_hex(key_id(key), want, sizeof want);
  TLV_ENSURE(m.is_signed, ErrorCode::kModelSignature,
             "the model is not signed; a signature by key %s is required (sign it with "
             "`tlvlink sign MODEL --key SECRET`)",
             want);
  to_hex(m.key_id, have, sizeof have);
  TLV_ENSURE(m.key_id == key_id(key), ErrorCode::kModelSignature,
             "the model is signed by key %s, not by the required key %s", have, want);
  const auto message = signed_message(m.hash);
  TLV_ENSURE(crypto_sign_verify_detached(m.signature.data(), message.data(), message.size(),
                                         key.bytes.data()) == 0,
             ErrorCode::kModelSignature,
             "the signature by key %s does not verify: the trailer was forged or corrupted", want);
  return {};
}

std::vector<std::byte> seal_model(std::span<const std::byte> body, const SecretKey* key) {
  (void)sodium_ready();
  uint8_t t[kTrailerBytes] = {};
  std::memcpy(t, kTrailerMagic, 4);
  t[4] = kTrailerVersion & 0xff;
  t[5] = kTrailerVersion >> 8;
  if (key != nullptr) {
    t[6] = kTrailerSigned;
    const KeyId id = key_id(public_half(*key));
    std::memcpy(t + 8, id.data(), id.size());
  }
  const ModelHash hash = hash_of(body, t);
  std::memcpy(t + kHashOffset, hash.data(), hash.size());
  if (key != nullptr) {
    const auto message = signed_message(hash);
    crypto_sign_detached(t + kSignatureOffset, nullptr, message.data(), message.size(),
                         key->bytes.data());
  }
  std::vector<std::byte> file(body.begin(), body.end());
  const auto* tb = reinterpret_cast<const std::byte*>(t);
  file.insert(file.end(), tb, tb + kTrailerBytes);
  return file;
}

}  // namespace tlvlink
