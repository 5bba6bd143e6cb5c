#pragma once
// Sealing, signing and re-writing whole model files (host side), on top of the trailer format
// of tlvlink/model_integrity.h. Each takes a file's bytes, validates it with Model::load, and
// returns the new file's bytes; writing them is the caller's job.
//
//   TLV_ASSIGN_OR_RETURN(KeyPair keys, generate_keypair());
//   TLV_TRY(write_key_files("/etc/tlvlink/model", keys));       // model.key (0600), model.pub
//   auto signed_file = sign_model(file_bytes, keys.secret);      // Result<vector<byte>>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "tlvlink/error.h"
#include "tlvlink/model.h"
#include "tlvlink/model_integrity.h"

namespace tlvlink::quantize {

// The same model written again by this writer: graph, constants, metadata and golden pairs kept
// index for index (model_copy.h), the golden pairs' head outputs recomputed, a new unsigned
// trailer. What `tlvlink upgrade` and the shipped models' regeneration use.
Result<std::vector<std::byte>> rewrite_model(const Model& model);

// A file written before the integrity trailer, checked against its legacy FNV-1a checksum and
// fully validated, then rewrite_model. A file that already has a trailer is checked and
// rewritten too (a no-op apart from the head outputs of files older than them).
Result<std::vector<std::byte>> upgrade_model(std::span<const std::byte> file);

// The file, fully validated (hash included), with a trailer signed by `key`. Re-signing a
// signed file replaces its signature.
Result<std::vector<std::byte>> sign_model(std::span<const std::byte> file, const SecretKey& key);

struct KeyPair {
  PublicKey public_key;
  SecretKey secret;
};
Result<KeyPair> generate_keypair();  // kBackend if libsodium cannot initialise

// Key file contents (model_integrity.h "Key files"), newline-terminated.
std::string format_public_key(const PublicKey& key);
std::string format_secret_key(const SecretKey& key);

// Writes BASE.key (the secret, mode 0600) and BASE.pub. Never overwrites: an existing file of
// either name is an error (kIo) naming it, so a key in use cannot be lost by a typo.
Status write_key_files(const std::string& base, const KeyPair& keys);
// Reads a secret key file; errors name the path.
Result<SecretKey> read_secret_key_file(const std::string& path);

}  // namespace tlvlink::quantize
