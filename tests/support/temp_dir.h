#pragma once
// A fresh directory under the system temp dir (mkdtemp), removed with everything in it.

#include <string>

namespace tlvlink::testing {

class TempDir {
 public:
  explicit TempDir(const std::string& tag = "test");  // tlvlink_<tag>_XXXXXX
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& rel) const { return path_ + "/" + rel; }

 private:
  std::string path_;
};

}  // namespace tlvlink::testing
