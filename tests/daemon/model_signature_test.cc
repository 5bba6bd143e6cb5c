// tlvlinkd with `model_public_key`: an unsigned model, one signed by another key, and one
// tampered with after signing stop the daemon at start with an error naming the model and the
// key; a model signed by the key starts.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "daemon/memory_source.h"
#include "support/temp_dir.h"
#include "tlvlink/atomic_file.h"
#include "tlvlink/daemon/config.h"
#include "tlvlink/daemon/session.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/quantize/model_sign.h"
#include "tlvlink/regular_file.h"

namespace tlvlink::daemon {
namespace {

constexpr const char* kModel = TLVLINK_SOURCE_DIR "/firmware/models/touch-tiny-int8.tlvm";
constexpr int32_t kW = 640, kH = 480;

// The runtime's own file helpers: this test also runs in cross builds, which have no host tools.
std::vector<std::byte> read_whole(const char* path) {
  auto f = RegularFile::open(path);
  EXPECT_TRUE(f.ok()) << path;
  if (!f.ok()) return {};
  std::vector<std::byte> bytes(f->size());
  EXPECT_TRUE(f->read_at(bytes, 0, path).ok()) << path;
  return bytes;
}

std::string config_text(const std::string& model, const std::string& key, const std::string& out) {
  return "model = \"" + model + "\"\nmodel_public_key = \"" + key + "\"\n" +
         "output = \"jsonl:" + out +
         "\"\nmax_frames = 4\n"
         "[[sensor]]\nname = \"left\"\nmodel = \"gelsight-mini\"\nfinger = \"A\"\n"
         "source = \"replay\"\ndevice = \"memory\"\nwidth = 640\nheight = 480\n";
}

std::vector<std::unique_ptr<capture::FrameSource>> one_source() {
  std::vector<uint8_t> grey(static_cast<size_t>(kW * kH * 3), 128);
  image::JpegEncoder enc;
  auto j = enc.encode({grey.data(), kW, kH, 3, 0}, 85, image::JpegEncoder::Subsampling::k422);
  EXPECT_TRUE(j.ok());
  std::vector<std::vector<uint8_t>> frames(4, std::vector<uint8_t>(j->begin(), j->end()));
  std::vector<std::unique_ptr<capture::FrameSource>> s;
  s.push_back(std::make_unique<testing::MemorySource>(
      "left", image::FrameFormat{image::PixelFormat::kMjpeg, kW, kH, 0}, frames, 100));
  EXPECT_TRUE(s.back()->start().ok());
  return s;
}

Result<std::unique_ptr<Session>> start(const std::string& model, const std::string& key,
                                       const std::string& out) {
  auto config = parse_config(config_text(model, key, out), "test.toml");
  EXPECT_TRUE(config.ok()) << config.error().message();
  if (!config.ok()) return config.error();
  return Session::start_with_sources(*config, one_source());
}

TEST(DaemonModelSignature, RefusesUnsignedWrongKeyAndTamperedModels) {
  testing::TempDir dir;
  auto keys = quantize::generate_keypair();
  auto other = quantize::generate_keypair();
  ASSERT_TRUE(keys.ok() && other.ok());
  const std::string base = dir.path() + "/model", other_base = dir.path() + "/other";
  ASSERT_TRUE(quantize::write_key_files(base, *keys).ok());
  ASSERT_TRUE(quantize::write_key_files(other_base, *other).ok());
  const std::string pub = base + ".pub", out = dir.path() + "/p.jsonl";
  const std::vector<std::byte> file = read_whole(kModel);
  ASSERT_FALSE(file.empty());
  auto good = quantize::sign_model(file, keys->secret);
  auto wrong = quantize::sign_model(file, other->secret);
  ASSERT_TRUE(good.ok() && wrong.ok());
  auto tampered = *good;
  tampered[tampered.size() - 20] ^= std::byte{1};  // inside the signature
  const std::string good_path = dir.path() + "/good.tlvm", wrong_path = dir.path() + "/wrong.tlvm",
                    tampered_path = dir.path() + "/tampered.tlvm";
  ASSERT_TRUE(write_file_atomic(good_path.c_str(), *good).ok());
  ASSERT_TRUE(write_file_atomic(wrong_path.c_str(), *wrong).ok());
  ASSERT_TRUE(write_file_atomic(tampered_path.c_str(), tampered).ok());

  struct Case {
    std::string model, expect;
  };
  for (const Case& c : {Case{kModel, "not signed"}, Case{wrong_path, "signed by key"},
                        Case{tampered_path, "does not verify"}}) {
    auto session = start(c.model, pub, out);
    ASSERT_FALSE(session.ok()) << c.model << " started";
    const std::string message = session.error().message();
    EXPECT_EQ(session.error().code(), ErrorCode::kModelSignature) << message;
    EXPECT_NE(message.find(c.expect), std::string::npos) << message;
    EXPECT_NE(message.find(c.model), std::string::npos) << "names the model: " << message;
    EXPECT_NE(message.find("model.pub"), std::string::npos) << "names the key: " << message;
  }
  auto session = start(good_path, pub, out);
  ASSERT_TRUE(session.ok()) << session.error().message();
  (*session)->stop();
}

TEST(DaemonModelSignature, MissingKeyFileIsAnError) {
  testing::TempDir dir;
  auto session = start(kModel, dir.path() + "/absent.pub", dir.path() + "/p.jsonl");
  ASSERT_FALSE(session.ok());
  EXPECT_NE(std::string(session.error().message()).find("absent.pub"), std::string::npos)
      << session.error().message();
}

}  // namespace
}  // namespace tlvlink::daemon
