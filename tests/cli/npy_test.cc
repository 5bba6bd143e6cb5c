// .npy reading and writing: round trips for every dtype and version, and every malformation
// rejected with an error that names the file.

#include <cstring>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tlvlink/io/file.h"
#include "tlvlink/io/npy.h"

namespace tlvlink::tools {
namespace {

std::vector<std::byte> bytes_of(std::string_view s) {
  std::vector<std::byte> b(s.size());
  std::memcpy(b.data(), s.data(), s.size());
  return b;
}

// A hand-built v1.0 file: magic, version, header length, header text, payload.
std::vector<std::byte> make_npy(std::string_view header, size_t payload_bytes, int major = 1) {
  std::string s("\x93NUMPY", 6);
  s.push_back(static_cast<char>(major));
  s.push_back('\0');
  const size_t len = header.size();
  s.push_back(static_cast<char>(len & 0xff));
  s.push_back(static_cast<char>((len >> 8) & 0xff));
  if (major == 2) s.append(2, '\0');
  s.append(header);
  s.append(payload_bytes, '\x01');
  return bytes_of(s);
}

std::string temp_path(const std::string& leaf) {
  return (std::filesystem::temp_directory_path() /
          ("tlvlink_npy_test_" + std::to_string(::getpid()) + "_" + leaf))
      .string();
}

// Expects a kFormat error whose message names `name` and contains `what`.
void expect_error(const std::vector<std::byte>& file, const std::string& what) {
  const std::string name = "bad/file.npy";
  auto r = parse_npy(file, name);
  ASSERT_FALSE(r.ok()) << "expected an error mentioning '" << what << "'";
  EXPECT_EQ(r.error().code(), ErrorCode::kFormat);
  const std::string msg = r.error().message();
  EXPECT_NE(msg.find(name), std::string::npos) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
}

template <typename T>
void round_trip(std::vector<int64_t> shape, std::vector<T> values, int version) {
  SCOPED_TRACE(::testing::Message() << "version " << version << " dtype " << sizeof(T));
  const NpyArray a = NpyArray::from<T>(shape, values);
  const std::string path = temp_path("rt.npy");
  ASSERT_TRUE(write_npy(path, a, version).ok());
  auto b = read_npy(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(b.ok()) << b.error().message();
  EXPECT_EQ(b->dtype, a.dtype);
  EXPECT_EQ(b->shape, a.shape);
  ASSERT_EQ(b->data, a.data);
  auto bytes = encode_npy(a, version);
  ASSERT_TRUE(bytes.ok());
  // numpy's layout: data starts on a 64-byte boundary, header ends in '\n'.
  const size_t data_offset = bytes->size() - a.data.size();
  EXPECT_EQ(data_offset % 64, 0u);
  EXPECT_EQ(static_cast<char>((*bytes)[data_offset - 1]), '\n');
  EXPECT_EQ(static_cast<int>((*bytes)[6]), version);
}

TEST(Npy, RoundTripsEveryDtypeAndVersion) {
  for (int version : {1, 2}) {
    round_trip<float>({2, 3}, {0.5f, -1.0f, 3.25f, 1e-30f, -0.0f, 7.0f}, version);
    round_trip<uint8_t>({1, 2, 2, 3}, {0, 1, 2, 3, 4, 5, 250, 251, 252, 253, 254, 255}, version);
    round_trip<int8_t>({4}, {-128, -1, 0, 127}, version);
    round_trip<int32_t>({2, 1, 1, 1, 1, 2}, {INT32_MIN, -1, 0, INT32_MAX}, version);
    round_trip<float>({}, {42.0f}, version);  // 0-d scalar
  }
}

TEST(Npy, ReadsNumpyStyleHeaderVariants) {
  // Key order, quotes and spacing as other writers produce them.
  const char* headers[] = {
      "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }                   \n",
      "{\"shape\": (2,3), \"descr\": \"<f4\", \"fortran_order\": False}\n",
      "{'fortran_order':False,'shape':(2,3,),'descr':'<f4'}",
  };
  for (const char* h : headers) {
    auto r = parse_npy(make_npy(h, 24), "x.npy");
    ASSERT_TRUE(r.ok()) << h << ": " << r.error().message();
    EXPECT_EQ(r->shape, (std::vector<int64_t>{2, 3}));
  }
}

TEST(Npy, RejectsMalformedFiles) {
  const std::string ok_header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }\n";
  expect_error(bytes_of("\x93NUMPZ\x01\x00"), "bad magic");
  expect_error(bytes_of("PK\x03\x04"), "bad magic");
  expect_error(bytes_of(std::string("\x93NUMPY\x01\x00\x10", 9)), "truncated .npy header");
  expect_error(bytes_of(std::string("\x93NUMPY\x03\x00\x10\x00", 10)), "version 3.0");
  {
    auto f = make_npy(ok_header, 24);
    f.resize(20);  // header length says 60 bytes, the file ends first
    expect_error(f, "runs past the end");
  }
  expect_error(make_npy(ok_header, 23), "truncated");
  expect_error(make_npy(ok_header, 25), "trailing bytes");
  expect_error(make_npy("{'descr': '>f4', 'fortran_order': False, 'shape': (2,), }", 8),
               "unsupported dtype '>f4'");
  expect_error(make_npy("{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }", 16),
               "unsupported dtype '<f8'");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", 24),
               "fortran_order is True");
  expect_error(make_npy("{'descr': '<f4', 'shape': (2, 3), }", 24), "lacks 'fortran_order'");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), 'x': 1}", 24),
               "unknown key 'x'");
  expect_error(
      make_npy("{'descr': '<f4', 'descr': '<f4', 'fortran_order': False, 'shape': (2,)}", 8),
      "repeats 'descr'");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, -3), }", 24),
               "not a non-negative integer");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 0), }", 0),
               "empty dimension");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (1,1,1,1,1,1,1), }", 4),
               "more than 6 dimensions");
  // Each dimension is plausible, the product overflows / exceeds the limit: rejected before
  // allocating.
  expect_error(
      make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2147483648, 2147483648, 4), }",
               0),
      "limit");
  expect_error(
      make_npy("{'descr': '|u1', 'fortran_order': False, 'shape': (99999999999999999999,), }", 0),
      "exceeds");
  expect_error(make_npy("{'descr': '|u1', 'fortran_order': False, 'shape': (1073741825,), }", 0),
               "limit");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), } junk", 24),
               "after the dict");
  expect_error(make_npy("{'descr': '<f4', 'fortran_order': Maybe, 'shape': (2, 3), }", 24),
               "True or False");
  expect_error(make_npy("{'descr': '<f4, 'fortran_order': False, 'shape': (2, 3)}", 24), "header");
}

TEST(Npy, FileErrorsNameThePath) {
  const std::string missing = temp_path("does_not_exist.npy");
  auto r = read_npy(missing);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code(), ErrorCode::kIo);
  EXPECT_NE(std::string(r.error().message()).find(missing), std::string::npos);

  const std::string path = temp_path("trunc.npy");
  auto full = encode_npy(NpyArray::from<float>({4}, std::vector<float>{1, 2, 3, 4}));
  ASSERT_TRUE(full.ok());
  full->resize(full->size() - 3);
  ASSERT_TRUE(write_file(path, *full).ok());
  auto t = read_npy(path);
  std::filesystem::remove(path);
  ASSERT_FALSE(t.ok());
  EXPECT_NE(std::string(t.error().message()).find(path), std::string::npos) << t.error().message();
  EXPECT_NE(std::string(t.error().message()).find("truncated"), std::string::npos)
      << t.error().message();
}

TEST(Npy, WriterRejectsInconsistentArrays) {
  NpyArray a = NpyArray::from<float>({2, 2}, std::vector<float>{1, 2, 3});
  EXPECT_FALSE(encode_npy(a).ok());
  a = NpyArray::from<float>({1, 1, 1, 1, 1, 1, 1}, std::vector<float>{1});
  EXPECT_FALSE(encode_npy(a).ok());
  EXPECT_FALSE(encode_npy(NpyArray::from<float>({1}, std::vector<float>{1}), 3).ok());
}

}  // namespace
}  // namespace tlvlink::tools
