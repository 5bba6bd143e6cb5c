// Writes seed models for the loader fuzzer: make_fuzz_corpus DIR
#include <cstdio>
#include <string>
#include <vector>

#include "model/tiny_models.h"

namespace {

bool write(const std::string& path, const std::vector<std::byte>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  return std::fclose(f) == 0 && ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_fuzz_corpus DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  using tlvlink::testing::TinyInt8Model;
  TinyInt8Model plain;
  TinyInt8Model with_metadata;
  with_metadata.tweak = [](tlvlink::quantize::ModelBuilder& b) {
    b.metadata().linear_heads.push_back({"hard_soft", {"hard", "soft"}, {1, 2, 3, 4}, {0, 0}});
    b.metadata().golden.push_back({std::vector<std::byte>(8 * 8 * 3 * 4), std::vector<std::byte>(8)});
  };
  TinyInt8Model depthwise_free;
  depthwise_free.conv.stride_h = depthwise_free.conv.stride_w = 2;
  depthwise_free.conv_output_shape = {1, 4, 4, 4};
  bool ok = write(dir + "/tiny_int8.tlvm", plain.build()) &&
            write(dir + "/tiny_int8_metadata.tlvm", with_metadata.build()) &&
            write(dir + "/tiny_int8_stride2.tlvm", depthwise_free.build());
  if (!ok) {
    std::fprintf(stderr, "make_fuzz_corpus: cannot write into %s\n", dir.c_str());
    return 1;
  }
  return 0;
}
