// A PNG the command wrote, as 8-bit RGB values to compare with what a test predicts.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <stb/stb_image.h>

namespace sphray::test {

struct Pixels {
  int width = 0, height = 0;
  std::vector<int> rgb;  // 3 values a pixel, rows from the top
  const int* at(int x, int y) const {
    return &rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                     static_cast<std::size_t>(x))];
  }
};

/// The image in file, or an empty one (width 0) when it cannot be read.
inline Pixels load_pixels(const std::string& file) {
  Pixels p;
  int channels = 0;
  stbi_uc* data = stbi_load(file.c_str(), &p.width, &p.height, &channels, 3);
  if (data == nullptr) return p;
  p.rgb.assign(data, data + 3 * p.width * p.height);
  stbi_image_free(data);
  return p;
}

}  // namespace sphray::test
