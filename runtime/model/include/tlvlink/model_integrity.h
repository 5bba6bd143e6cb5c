#pragma once
// The integrity trailer every .tlvm file ends with: a BLAKE2b-256 hash of every byte before it
// (and of its own header), and optionally an ed25519 signature of that hash. Byte layout and
// how to recompute it: runtime/README.md "Integrity trailer". Model::load checks it before it
// reads anything else; these functions are the one implementation of the format, for the loader,
// the writer (quantize/writer) and `tlvlink sign` / `verify --public-key`.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "tlvlink/error.h"

namespace tlvlink {

inline constexpr size_t kTrailerBytes = 112;
inline constexpr uint16_t kTrailerVersion = 1;
inline constexpr char kTrailerMagic[4] = {'T', 'L', 'V', 'H'};
inline constexpr uint16_t kTrailerSigned = 1;  // flags bit 0; the other 15 bits must be 0

using ModelHash = std::array<uint8_t, 32>;  // BLAKE2b-256
using KeyId = std::array<uint8_t, 8>;       // first 8 bytes of BLAKE2b-256(public key)
using Signature = std::array<uint8_t, 64>;  // ed25519, detached
struct PublicKey {
  std::array<uint8_t, 32> bytes{};
};
struct SecretKey {  // libsodium's form: 32-byte seed then the 32-byte public key
  std::array<uint8_t, 64> bytes{};
};

// A checked trailer. `body_size` is the flatbuffer's size (file size - kTrailerBytes).
struct ModelIntegrity {
  size_t body_size = 0;
  bool is_signed = false;
  KeyId key_id{};  // zero when unsigned
  ModelHash hash{};
  Signature signature{};  // zero when unsigned
};

// Whether the file ends with the trailer's magic (files written before it do not).
bool has_integrity_trailer(std::span<const std::byte> file);

// Reads and checks the trailer of a whole model file: magic, version, flags, a zero key id and
// signature when unsigned, and (when `check_hash`) the hash. Errors (kModelChecksum) say which:
// no trailer (a file from before the trailer: upgrade with `tlvlink upgrade`), another version,
// or a hash mismatch with both values.
Result<ModelIntegrity> read_integrity(std::span<const std::byte> file, bool check_hash = true);

// Whether `integrity` carries a valid signature by `key` (kModelSignature: unsigned, signed by
// another key (both ids named) or a signature that does not verify).
Status check_signature(const ModelIntegrity& integrity, const PublicKey& key);

// `body` (a flatbuffer) followed by its trailer; signed when `key` is given. Allocates.
std::vector<std::byte> seal_model(std::span<const std::byte> body, const SecretKey* key = nullptr);

KeyId key_id(const PublicKey& key);
// Lower-case hex of any byte array (what messages and `tlvlink inspect` print).
void to_hex(std::span<const uint8_t> bytes, char* out, size_t out_size);

// Key files: one text line, "tlvlink-ed25519-public-key <64 hex digits>" or
// "tlvlink-ed25519-secret-key <128 hex digits>". parse_* check the prefix, length and digits,
// and that a secret key's public half matches its seed.
Result<PublicKey> parse_public_key(std::span<const char> text);
Result<SecretKey> parse_secret_key(std::span<const char> text);
// Reads a public key file (the daemon's `[model] public_key`); errors name the path.
Result<PublicKey> read_public_key_file(const char* path);
PublicKey public_half(const SecretKey& key);

}  // namespace tlvlink
