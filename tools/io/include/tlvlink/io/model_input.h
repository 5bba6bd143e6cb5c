#pragma once
// A model's input from a file, as `tlvlink infer` takes it: the format is told by the file's
// magic bytes, never by its name.
//   .npy ("\x93NUMPY")          a tensor shaped and typed like graph input 0, copied as-is; or a
//                               uint8 image [H,W,C] / [1,H,W,C] for a float input
//   PPM / PGM ("P6", "P5")      binary, maxval 255
//   JPEG ("\xff\xd8\xff")       through runtime/image (libturbojpeg)
//   PNG ("\x89PNG\r\n\x1a\n")   through libpng
// Images are preprocessed by the model's input spec (image::preprocess) into a float input.
//
//   TLV_TRY(tools::load_model_input("frame.jpg", model, executor.input(0)));

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "tlvlink/error.h"
#include "tlvlink/io/image.h"
#include "tlvlink/model.h"

namespace tlvlink::tools {

enum class InputFileKind : uint8_t { kUnknown = 0, kNpy, kPnm, kJpeg, kPng };
InputFileKind sniff_input_file(std::span<const std::byte> bytes);

// An image file's bytes decoded by their magic (PPM/PGM, JPEG, PNG, or a uint8 .npy image).
// `name` prefixes errors; kFormat for anything else.
Result<Image> decode_image_file(std::span<const std::byte> bytes, const std::string& name);

// Fills `dst` (graph input 0 of `model`, its exact byte size) from the file at `path`. Errors
// name the path: unreadable (kIo), unknown or malformed format (kFormat), a tensor that does
// not match the input (kShapeMismatch), an image for a non-float input (kModelUnsupported).
Status load_model_input(const std::string& path, const Model& model, std::span<std::byte> dst);
// The same, with an image read as a tactile sensor's processed view first (sensor_frame.h:
// `sensor` named or, when empty, detected from the frame size; a camera frame is cut to its view
// as tlvlinkd cuts it). `note` receives what was done to the image, or stays empty.
Status load_sensor_input(const std::string& path, std::string_view sensor, const Model& model,
                         std::span<std::byte> dst, std::string& note);
// An image already decoded (a sensor's view, sensor_frame.h) through the model's preprocessing.
Status model_input_from_image(const Image& image, const std::string& name, const Model& model,
                              std::span<std::byte> dst);
// The same on bytes already in memory.
Status model_input_from_bytes(std::span<const std::byte> bytes, const std::string& name,
                              const Model& model, std::span<std::byte> dst);

}  // namespace tlvlink::tools
