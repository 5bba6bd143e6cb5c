#pragma once
// Loading a model file for a host tool: Model::load_file (regular files only, size and
// identifier checked before reading; the path in every error).

#include <memory>
#include <string>

#include "tlvlink/error.h"
#include "tlvlink/model.h"

namespace tlvlink::tools {

Result<std::unique_ptr<Model>> load_model(const std::string& path);

}  // namespace tlvlink::tools
