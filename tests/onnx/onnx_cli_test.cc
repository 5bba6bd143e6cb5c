// `tlvlink convert` through the real binary: exit code 0 with a model that loads, 1 for a model
// it cannot convert (the op and node named on stderr), 2 for bad arguments.

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "tlvlink/model.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

using ::tlvlink::testing::CliRun;

using ::tlvlink::testing::run_tlvlink;

class ConvertCli : public ::testing::Test {
 protected:
  static std::string model(const std::string& name) {
    return std::string(TLVLINK_ONNX_MODELS) + "/" + name + ".onnx";
  }
  std::string out(const std::string& leaf) const { return (dir_ / leaf).string(); }
  ::tlvlink::testing::TempDir tmp_{"convert"};  // a fresh directory, removed with the fixture
  fs::path dir_ = tmp_.path();
};

TEST_F(ConvertCli, ConvertsAndTheModelLoads) {
  const CliRun r = run_tlvlink("convert " + model("mobilenetv2_blocks") + " -o " + out("m.tlvm") +
                               " --mean 0.485,0.456,0.406 --std 0.229,0.224,0.225 --name mnv2");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("opset 13"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[1, 64, 64, 3]"), std::string::npos) << r.out;
  auto m = Model::load_file(out("m.tlvm").c_str());
  ASSERT_TRUE(m.ok()) << m.error().message();
  EXPECT_EQ((*m)->metadata().name, "mnv2");
  EXPECT_FLOAT_EQ((*m)->metadata().input.std[2], 0.225f);
  EXPECT_EQ(run_tlvlink("inspect " + out("m.tlvm")).exit_code, 0);
}

TEST_F(ConvertCli, UnsupportedOpExitsOneNamingOpAndNode) {
  const CliRun r = run_tlvlink("convert " + model("reject_softmax") + " -o " + out("s.tlvm"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("'Softmax'"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("/2/Softmax"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out("s.tlvm")));
}

TEST_F(ConvertCli, BadArgumentsExitTwo) {
  EXPECT_EQ(run_tlvlink("convert " + model("conv_dense_relu")).exit_code, 2);  // no -o
  EXPECT_EQ(run_tlvlink("convert " + out("missing.onnx") + " -o " + out("x.tlvm")).exit_code, 2);
  EXPECT_EQ(run_tlvlink("convert " + model("conv_dense_relu") + " -o " + out("x.tlvm") +
                        " --channel-order yuv")
                .exit_code,
            2);
  // Two means for a three-channel input: a usage error found after reading the model.
  const CliRun r = run_tlvlink("convert " + model("conv_dense_relu") + " -o " + out("x.tlvm") +
                               " --mean 0.1,0.2");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.out.find("mean has 2 values"), std::string::npos) << r.out;
}

TEST_F(ConvertCli, HelpListsTheOptions) {
  const CliRun r = run_tlvlink("convert --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* s : {"--mean", "--std", "--channel-order", "--output", "Exit codes"}) {
    EXPECT_NE(r.out.find(s), std::string::npos) << s << " missing from:\n" << r.out;
  }
}

}  // namespace
}  // namespace tlvlink
