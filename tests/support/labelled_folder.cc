#include "support/labelled_folder.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

namespace tlvlink::testing {

void write_colour_folder(const std::filesystem::path& dir, int objects_per_class, int width,
                         int height) {
  uint32_t state = 12345;
  auto noise = [&state] {
    state = state * 1664525u + 1013904223u;
    return static_cast<int>((state >> 24) % 21) - 10;
  };
  for (const char* cls : {"warm", "cool"}) {
    for (int o = 0; o < objects_per_class; ++o) {
      const std::filesystem::path group = dir / cls / ("object" + std::to_string(o));
      std::filesystem::create_directories(group);
      for (int f = 0; f < 4; ++f) {
        std::ofstream out(group / ("frame" + std::to_string(f) + ".ppm"), std::ios::binary);
        out << "P6\n" << width << " " << height << "\n255\n";
        const bool warm = cls[0] == 'w';
        for (int i = 0; i < width * height; ++i) {
          const int base = 90 + 15 * o;
          const int rgb[3] = {base + (warm ? 40 : 0), base, base + (warm ? 0 : 40)};
          for (int c : rgb) out.put(static_cast<char>(std::clamp(c + noise(), 0, 255)));
        }
      }
    }
  }
}

}  // namespace tlvlink::testing
