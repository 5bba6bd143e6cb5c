// Cross-architecture parity of both executors. On x86-64, TLVLINK_PARITY_RECORD=1 runs every
// model in $TLVLINK_PARITY_DIR (made by `tlvlink gen-reference`) on a fixed set of inputs and
// records inputs and outputs; on any other build (aarch64 under qemu) the same inputs must give
// int8 outputs identical to the recording, and fp32 outputs within kFloatRelTolerance.
//
// Files per model M.tlvm and input case C: M.C.in (input bytes), M.C.<executor>.out (output 0),
// M.C.<executor>.t<N>.int8 (int8 tensor N entering a Dequantize, compared bit for bit).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/test_models.h"
#include "tlvlink/executor.h"
#include "tlvlink/model.h"

namespace tlvlink {
namespace {

namespace fs = std::filesystem;

// fp32 kernels differ between architectures in summation order and FMA use (XNNPACK's SSE/AVX
// vs NEON microkernels), so equality is not expected; 1e-4 of the output's largest magnitude is
// ~100x the float rounding of a 37 MMAC network and well below any meaningful embedding change.
constexpr double kFloatRelTolerance = 1e-4;

std::vector<char> read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void write_bytes(const fs::path& p, std::span<const std::byte> b) {
  std::ofstream f(p, std::ios::binary);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// Inputs: the model's golden frames plus the stiff cases (all-zero, the input range's two
// extremes in a checkerboard, uniform noise), all derived from the float input's size.
std::vector<std::pair<std::string, std::vector<std::byte>>> make_inputs(const Model& m) {
  std::vector<std::pair<std::string, std::vector<std::byte>>> cases;
  for (size_t i = 0; i < m.metadata().golden.size(); ++i) {
    const auto& in = m.metadata().golden[i].input;
    cases.emplace_back("golden" + std::to_string(i), std::vector<std::byte>(in.begin(), in.end()));
  }
  const Tensor& t = m.graph().tensor(m.graph().inputs[0]);
  const size_t n = t.bytes() / sizeof(float);
  std::vector<float> zeros(n, 0.0f), checker(n), noise(n);
  uint64_t state = 0x9E3779B97F4A7C15ull;  // splitmix64: identical on every platform
  for (size_t i = 0; i < n; ++i) {
    checker[i] = ((i / 3) % 2 == 0) ? -2.0f : 2.0f;  // (0 - 0.5)/0.25 and (1 - 0.5)/0.25
    state += 0x9E3779B97F4A7C15ull;
    uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    noise[i] = static_cast<float>(z >> 40) / static_cast<float>(1 << 24) * 4.0f - 2.0f;
  }
  for (auto* v : {&zeros, &checker, &noise}) {
    const auto* b = reinterpret_cast<const std::byte*>(v->data());
    cases.emplace_back(v == &zeros     ? "zeros"
                       : v == &checker ? "checker"
                                       : "noise",
                       std::vector<std::byte>(b, b + n * sizeof(float)));
  }
  return cases;
}

// The int8 tensors the model dequantizes (where its int8 region ends).
std::vector<int32_t> dequantize_inputs(const Graph& g) {
  std::vector<int32_t> out;
  for (const Operator& op : g.operators)
    if (op.type == OpType::kDequantize) out.push_back(op.inputs[0]);
  return out;
}

TEST(CrossArchParity, OutputsMatchTheX86Recording) {
  const char* dir_env = std::getenv("TLVLINK_PARITY_DIR");
  if (dir_env == nullptr || !fs::exists(dir_env)) {
    GTEST_SKIP() << "no recording in TLVLINK_PARITY_DIR (tools/setup/cross_test.sh makes one)";
  }
  const fs::path dir(dir_env);
  const bool record = std::getenv("TLVLINK_PARITY_RECORD") != nullptr;
  std::vector<fs::path> models;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".tlvm") models.push_back(e.path());
  }
  std::sort(models.begin(), models.end());
  ASSERT_FALSE(models.empty()) << "no .tlvm files in " << dir;
  int compared = 0;
  for (const fs::path& path : models) {
    SCOPED_TRACE(path.string());
    const std::vector<char> raw = read_bytes(path);
    auto model = testing::load_model(
        std::vector<std::byte>(reinterpret_cast<const std::byte*>(raw.data()),
                               reinterpret_cast<const std::byte*>(raw.data()) + raw.size()));
    ASSERT_NE(model, nullptr);
    const Tensor& out = model->graph().tensor(model->graph().outputs[0]);
    // An int8 model's float output is a Dequantize of int8 values: identical int8 values give
    // identical bytes.
    const Operator& last = model->graph().operators.back();
    const bool int8_model =
        last.output == model->graph().outputs[0] && last.type == OpType::kDequantize;
    for (ExecutorKind kind : {ExecutorKind::kXnnpack, ExecutorKind::kReference}) {
      ExecutorOptions options;
      options.expose_all_tensors = true;  // the int8 tensors entering each Dequantize
      auto exec = make_executor(*model, kind, options);
      ASSERT_TRUE(exec.ok()) << exec.error().message();
      for (const auto& [name, input] : make_inputs(*model)) {
        const std::string stem = path.stem().string() + "." + name;
        SCOPED_TRACE(stem + " on " + executor_kind_name(kind));
        const fs::path in_file = dir / (stem + ".in");
        const fs::path out_file = dir / (stem + "." + executor_kind_name(kind) + ".out");
        std::vector<std::byte> feed = input;
        if (!record) {
          const std::vector<char> rec = read_bytes(in_file);
          ASSERT_EQ(rec.size(), input.size()) << in_file << " missing or of another size";
          std::memcpy(feed.data(), rec.data(), rec.size());
        }
        std::memcpy((*exec)->input(0).data(), feed.data(), feed.size());
        ASSERT_TRUE((*exec)->invoke().ok());
        const std::span<const std::byte> got = (*exec)->output(0);
        // Every int8 tensor leaving the int8 region must be bit-identical, also in a mixed
        // model whose output comes from an fp32 layer after the Dequantize (the shipped one).
        for (const int32_t q : dequantize_inputs(model->graph())) {
          auto bytes = (*exec)->tensor(q);
          ASSERT_TRUE(bytes.ok()) << bytes.error().message();
          const fs::path q_file =
              dir / (stem + "." + executor_kind_name(kind) + ".t" + std::to_string(q) + ".int8");
          if (record) {
            write_bytes(q_file, *bytes);
          } else {
            const std::vector<char> want_q = read_bytes(q_file);
            ASSERT_EQ(want_q.size(), bytes->size()) << q_file << " missing or of another size";
            EXPECT_EQ(std::memcmp(want_q.data(), bytes->data(), bytes->size()), 0)
                << "int8 tensor " << model->graph().tensor(q).name
                << " differs from the x86-64 recording";
          }
        }
        if (record) {
          write_bytes(in_file, feed);
          write_bytes(out_file, got);
          continue;
        }
        const std::vector<char> want_raw = read_bytes(out_file);
        ASSERT_EQ(want_raw.size(), got.size()) << out_file;
        const auto* want = reinterpret_cast<const float*>(want_raw.data());
        const auto* have = reinterpret_cast<const float*>(got.data());
        const size_t n = got.size() / sizeof(float);
        ASSERT_EQ(out.dtype, DType::kFloat32);
        if (int8_model) {
          EXPECT_EQ(std::memcmp(want_raw.data(), got.data(), got.size()), 0)
              << "int8 model output differs from the x86-64 recording";
        } else {
          double max_ref = 0, max_err = 0;
          for (size_t k = 0; k < n; ++k) {
            max_ref = std::max(max_ref, std::fabs(static_cast<double>(want[k])));
            max_err = std::max(
                max_err, std::fabs(static_cast<double>(want[k]) - static_cast<double>(have[k])));
          }
          EXPECT_LE(max_err, kFloatRelTolerance * max_ref);
          std::printf("%s %s: fp32 max |diff| %.3g (max |x| %.3g)\n", stem.c_str(),
                      executor_kind_name(kind), max_err, max_ref);
        }
        ++compared;
      }
    }
  }
  if (record) {
    std::printf("recorded %zu models into %s\n", models.size(), dir.c_str());
  } else {
    std::printf("compared %d outputs with the recording\n", compared);
  }
}

}  // namespace
}  // namespace tlvlink
