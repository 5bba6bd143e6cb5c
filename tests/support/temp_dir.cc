#include "support/temp_dir.h"

#include <stdlib.h>

#include <cstdlib>
#include <filesystem>

namespace tlvlink::testing {

TempDir::TempDir(const std::string& tag) {
  std::string tmpl =
      (std::filesystem::temp_directory_path() / ("tlvlink_" + tag + "_XXXXXX")).string();
  if (::mkdtemp(tmpl.data()) == nullptr) std::abort();  // no temp dir: nothing can be tested
  path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

}  // namespace tlvlink::testing
