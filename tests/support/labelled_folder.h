#pragma once
// A labelled frame folder as a user makes one (DIR/<class>/<object>/frameN.ppm): class "warm"
// redder than "cool", each object with its own brightness, 4 frames per object with noise.
// Frames are `width` x `height` PPM (320x240: a processed view's size). Seeded: the same bytes
// every run.

#include <filesystem>

namespace tlvlink::testing {

void write_colour_folder(const std::filesystem::path& dir, int objects_per_class = 3,
                         int width = 320, int height = 240);

}  // namespace tlvlink::testing
