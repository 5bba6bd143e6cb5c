#include "tlvlink/io/model_file.h"

namespace tlvlink::tools {

Result<std::unique_ptr<Model>> load_model(const std::string& path) {
  auto model = Model::load_file(path.c_str());
  if (!model.ok()) return model.error().with_context("%s", path.c_str());
  return std::move(model).value();
}

}  // namespace tlvlink::tools
