// A model's input from a file by its magic bytes (model_input.h); what `tlvlink infer` reads.

#include "tlvlink/io/model_input.h"

#include <algorithm>
#include <cstring>
#include <string_view>
#include <vector>

#include "tlvlink/image/decode_budget.h"
#include "tlvlink/image/jpeg.h"
#include "tlvlink/image/preprocess.h"
#include "tlvlink/io/file.h"
#include "tlvlink/io/format.h"
#include "tlvlink/io/npy.h"
#include "tlvlink/io/npy_image.h"
#include "tlvlink/io/png.h"
#include "tlvlink/io/pnm.h"
#include "tlvlink/io/sensor_frame.h"

namespace tlvlink::tools {
namespace {

bool starts_with(std::span<const std::byte> b, std::string_view prefix) {
  return b.size() >= prefix.size() && std::memcmp(b.data(), prefix.data(), prefix.size()) == 0;
}

Status image_input(const Image& image, const std::string& name, const Model& model,
                   std::span<std::byte> dst) {
  const Tensor& in = model.graph().tensor(model.graph().inputs[0]);
  TLV_ENSURE(in.dtype == DType::kFloat32, ErrorCode::kModelUnsupported,
             "model input is %s; images can only feed float inputs", dtype_name(in.dtype));
  auto x = image::preprocess(image, model.metadata().input);
  if (!x.ok()) return x.error().with_context("%s", name.c_str());
  TLV_ENSURE(x->size() * sizeof(float) == dst.size(), ErrorCode::kShapeMismatch,
             "%s: preprocessing gave %zu values, model input %s needs %zu", name.c_str(), x->size(),
             shape_string(in.shape).c_str(), dst.size() / sizeof(float));
  std::memcpy(dst.data(), x->data(), dst.size());
  return {};
}

}  // namespace

Status model_input_from_image(const Image& image, const std::string& name, const Model& model,
                              std::span<std::byte> dst) {
  return image_input(image, name, model, dst);
}

InputFileKind sniff_input_file(std::span<const std::byte> bytes) {
  if (starts_with(bytes, "\x93NUMPY")) return InputFileKind::kNpy;
  if (starts_with(bytes, "P6") || starts_with(bytes, "P5")) return InputFileKind::kPnm;
  if (starts_with(bytes, "\xff\xd8\xff")) return InputFileKind::kJpeg;
  if (starts_with(bytes, "\x89PNG\r\n\x1a\n")) return InputFileKind::kPng;
  return InputFileKind::kUnknown;
}

Result<Image> decode_image_file(std::span<const std::byte> bytes, const std::string& name) {
  switch (sniff_input_file(bytes)) {
    case InputFileKind::kNpy: {
      TLV_ASSIGN_OR_RETURN(NpyArray a, parse_npy(bytes, name));
      return image_from_npy(a, name);
    }
    case InputFileKind::kPnm: return parse_pnm(bytes, name);
    case InputFileKind::kJpeg:
      return image::decode_jpeg(
          std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()),
          name);
    case InputFileKind::kPng: return decode_png(bytes, name);
    case InputFileKind::kUnknown: break;
  }
  return Error::make(ErrorCode::kFormat,
                     "%s: neither a .npy file nor a PPM/PGM (binary), JPEG or PNG image",
                     name.c_str());
}

Status model_input_from_bytes(std::span<const std::byte> bytes, const std::string& name,
                              const Model& model, std::span<std::byte> dst) {
  const Graph& g = model.graph();
  const Tensor& in = g.tensor(g.inputs[0]);
  if (sniff_input_file(bytes) == InputFileKind::kNpy) {
    TLV_ASSIGN_OR_RETURN(NpyArray a, parse_npy(bytes, name));
    const bool image_like = a.dtype == DType::kUInt8 && in.dtype != DType::kUInt8;
    if (!image_like) {
      const bool same_shape = a.shape.size() == in.shape.rank &&
                              std::equal(a.shape.begin(), a.shape.end(), in.shape.dims.begin());
      // Float models also take uint8 images: the hint helps when one was saved as int8/float32.
      TLV_ENSURE(a.dtype == in.dtype && same_shape, ErrorCode::kShapeMismatch,
                 "%s: %s tensor of shape %s does not match model input '%.*s' %s %s%s",
                 name.c_str(), dtype_name(a.dtype), npy_shape_string(a.shape).c_str(),
                 static_cast<int>(in.name.size()), in.name.data(), dtype_name(in.dtype),
                 shape_string(in.shape).c_str(),
                 in.dtype == DType::kFloat32 ? " (images: uint8 [H,W,C] or [1,H,W,C])" : "");
      TLV_ENSURE(a.data.size() == dst.size(), ErrorCode::kShapeMismatch,
                 "%s: %zu data bytes for an input of %zu", name.c_str(), a.data.size(), dst.size());
      std::memcpy(dst.data(), a.data.data(), dst.size());
      return {};
    }
    TLV_ASSIGN_OR_RETURN(const Image image, image_from_npy(a, name));
    return image_input(image, name, model, dst);
  }
  TLV_ASSIGN_OR_RETURN(const Image image, decode_image_file(bytes, name));
  return image_input(image, name, model, dst);
}

namespace {

// The largest file that can feed the model: a tensor of its input's size, or an image within
// the decode budget (the pixel cap's RGB bytes as raw .npy / PNM, the largest case).
Result<std::vector<std::byte>> read_input_file(const std::string& path, size_t input_bytes) {
  const size_t image_limit = static_cast<size_t>(image::kMaxImagePixels) * 3;
  return read_file(path, std::max(input_bytes, image_limit) + kMaxNpyHeaderBytes);
}

}  // namespace

Status load_model_input(const std::string& path, const Model& model, std::span<std::byte> dst) {
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_input_file(path, dst.size()));
  return model_input_from_bytes(bytes, path, model, dst);
}

Status load_sensor_input(const std::string& path, std::string_view sensor, const Model& model,
                         std::span<std::byte> dst, std::string& note) {
  note.clear();
  TLV_ASSIGN_OR_RETURN(std::vector<std::byte> bytes, read_input_file(path, dst.size()));
  if (sniff_input_file(bytes) == InputFileKind::kNpy && sensor.empty()) {
    return model_input_from_bytes(bytes, path, model, dst);  // a tensor, or an image as it is
  }
  TLV_ASSIGN_OR_RETURN(SensorFrame frame, sensor_frame_from_bytes(bytes, path, sensor));
  TLV_TRY(check_trained_sensor(model, frame, path));
  note = frame.note;
  return image_input(frame.view, path, model, dst);
}

}  // namespace tlvlink::tools
