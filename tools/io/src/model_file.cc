#include "tlvlink/io/model_file.h"

namespace tlvlink::tools {

// Model::load_file already names the path in every error (and opens regular files only).
Result<std::unique_ptr<Model>> load_model(const std::string& path) {
  return Model::load_file(path.c_str());
}

}  // namespace tlvlink::tools
