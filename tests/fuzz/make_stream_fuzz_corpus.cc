// Writes the seed corpus of stream_decoder_fuzz into a directory: every message type as a
// framed stream (even first byte) and as a bare payload (odd first byte), plus streams with
// several frames, garbage between them and a frame of another major version.
//   make_stream_fuzz_corpus DIR

#include <cstdio>
#include <string>
#include <vector>

#include "protocol/message_samples.h"
#include "tlvlink/protocol/encode.h"

namespace {

using namespace tlvlink;
using namespace tlvlink::protocol;

alignas(8) std::byte g_scratch[kEncodeBufferSize];
std::byte g_wire[kMaxWireFrameSize];

bool write(const std::string& path, const std::vector<std::byte>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  return std::fclose(f) == 0 && ok;
}

template <typename M>
bool seed(const std::string& dir, const char* name, const M& m, std::vector<std::byte>& all) {
  Result<std::span<const std::byte>> payload = encode_payload(m, g_scratch);
  if (!payload.ok()) return false;
  std::vector<std::byte> p = {std::byte{1}};
  p.insert(p.end(), payload.value().begin(), payload.value().end());
  FrameHeader h;
  h.type = MessageTypeOf<M>::value;
  Result<size_t> n = encode_frame(h, payload.value(), g_wire);
  if (!n.ok()) return false;
  std::vector<std::byte> s = {std::byte{0}, std::byte{0x3F}};  // stream mode, 64-byte pieces
  s.insert(s.end(), g_wire, g_wire + n.value());
  all.insert(all.end(), g_wire, g_wire + n.value());
  all.push_back(std::byte{0x42});  // garbage between frames
  return write(dir + "/payload_" + name, p) && write(dir + "/stream_" + name, s);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_stream_fuzz_corpus DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  std::vector<std::byte> all = {std::byte{0}, std::byte{0xFF}};
  bool ok = seed(dir, "hello", testing::sample_hello(), all) &&
            seed(dir, "frame", testing::sample_frame_prediction(true), all) &&
            seed(dir, "grasp", testing::sample_grasp_prediction(), all) &&
            seed(dir, "grasp_not", testing::sample_grasp_not_computed(), all) &&
            seed(dir, "stats", testing::sample_stats(), all) &&
            seed(dir, "error", testing::sample_error(), all) &&
            seed(dir, "ack", testing::sample_ack(), all) &&
            seed(dir, "nack", testing::sample_nack(), all) &&
            seed(dir, "pong", testing::sample_pong(), all) &&
            seed(dir, "command", testing::sample_command(), all);
  FrameHeader future;
  future.version_major = 2;
  Result<size_t> n = encode_message(testing::sample_ack(), future, g_scratch, g_wire);
  ok = ok && n.ok();
  if (n.ok()) all.insert(all.end(), g_wire, g_wire + n.value());
  ok = ok && write(dir + "/stream_all", all);
  if (!ok)
    std::fprintf(stderr, "make_stream_fuzz_corpus: could not write the seeds into %s\n",
                 dir.c_str());
  return ok ? 0 : 1;
}
