// tlvlink_model_load_bench MODEL... [--loads N]: what the integrity trailer costs at load.
// Each model is loaded from memory (file I/O excluded) N times in three variants, interleaved
// load by load so a burst of machine load hits every variant alike: without the hash check
// (verify_checksum off), with it (the default), and with hash + ed25519 signature (a key made
// for the run, the model signed in memory). Prints medians and the ratios to the unchecked load.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "tlvlink/model.h"
#include "tlvlink/quantize/model_sign.h"

namespace {

std::vector<std::byte> read_all(const char* path) {
  std::vector<std::byte> bytes;
  std::FILE* f = std::fopen(path, "rb");
  if (f == nullptr) return bytes;
  std::byte chunk[1 << 16];
  size_t n = 0;
  while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0)
    bytes.insert(bytes.end(), chunk, chunk + n);
  std::fclose(f);
  return bytes;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tlvlink;
  int loads = 200;
  std::vector<const char*> models;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--loads") == 0 && i + 1 < argc) {
      loads = std::max(1, std::atoi(argv[++i]));
    } else {
      models.push_back(argv[i]);
    }
  }
  if (models.empty()) {
    std::fprintf(stderr, "usage: %s MODEL... [--loads N]\n", argv[0]);
    return 2;
  }
  auto keys = quantize::generate_keypair();
  if (!keys.ok()) return 1;
  std::printf(
      "| model | bytes | load, no check (ms) | + hash (ms) | + hash + signature (ms) | ratios |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const char* path : models) {
    const std::vector<std::byte> file = read_all(path);
    auto signed_file = quantize::sign_model(file, keys->secret);
    if (!signed_file.ok()) {
      std::fprintf(stderr, "%s: %s\n", path, signed_file.error().message());
      return 1;
    }
    const LoadOptions variants[3] = {
        {.verify_checksum = false}, {}, {.public_key = &keys->public_key}};
    const std::vector<std::byte>* inputs[3] = {&file, &file, &*signed_file};
    std::vector<double> ms[3];
    for (int k = 0; k < loads; ++k) {
      for (int v = 0; v < 3; ++v) {
        const auto t0 = std::chrono::steady_clock::now();
        auto m = Model::load(*inputs[v], variants[v]);
        const auto t1 = std::chrono::steady_clock::now();
        if (!m.ok()) {
          std::fprintf(stderr, "%s: %s\n", path, m.error().message());
          return 1;
        }
        ms[v].push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      }
    }
    const double a = median(ms[0]), b = median(ms[1]), c = median(ms[2]);
    std::printf("| %s | %zu | %.3f | %.3f | %.3f | %.2fx / %.2fx |\n", path, file.size(), a, b, c,
                b / a, c / a);
  }
  std::printf("medians of %d loads per variant, interleaved\n", loads);
  return 0;
}
