#include "sphray/render/image_file.hpp"

#include "image/atomic_output.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO  // we write through our own file descriptor
#include <stb/stb_image_write.h>

namespace sphray::render {
namespace {

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The PNG in one buffer from stb_image_write (malloc'd), written out whole.
void write_png(const Image& image, detail::AtomicOutput& out, const std::filesystem::path& path) {
  int size = 0;
  unsigned char* png =
      stbi_write_png_to_mem(image.rgb.data(), image.width * 3, image.width, image.height, 3, &size);
  if (png == nullptr) throw IoError(path.string() + ": cannot encode the image");
  try {
    out.write(png, static_cast<std::size_t>(size));
  } catch (...) {
    std::free(png);
    throw;
  }
  std::free(png);
}

// P3 as the book writes it: a header, then one "r g b" line per pixel, written in pieces of
// about a megabyte so the text (up to 12 bytes a pixel) never has to fit in memory at once.
void write_ppm(const Image& image, detail::AtomicOutput& out) {
  constexpr std::size_t kChunk = std::size_t{1} << 20;
  char line[32];
  std::snprintf(line, sizeof line, "P3\n%d %d\n255\n", image.width, image.height);
  std::string text(line);
  text.reserve(kChunk + sizeof line);
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    std::snprintf(line, sizeof line, "%d %d %d\n", image.rgb[i], image.rgb[i + 1],
                  image.rgb[i + 2]);
    text.append(line);
    if (text.size() >= kChunk) {
      out.write(text.data(), text.size());
      text.clear();
    }
  }
  out.write(text.data(), text.size());
}

}  // namespace

std::optional<ImageFormat> image_format_for(const std::filesystem::path& path) {
  std::string extension = lowercase(path.extension().string());
  if (extension == ".png") return ImageFormat::png;
  if (extension == ".ppm") return ImageFormat::ppm;
  return std::nullopt;
}

PendingImageFile::PendingImageFile(std::filesystem::path target, bool replace_read_only)
    : target_(std::move(target)) {
  std::optional<ImageFormat> format = image_format_for(target_);
  if (!format) {
    throw std::invalid_argument(target_.string() +
                                ": expected an output file ending in .png or .ppm");
  }
  format_ = *format;
  output_ = std::make_unique<detail::AtomicOutput>(target_, replace_read_only);
}

PendingImageFile::~PendingImageFile() = default;

void PendingImageFile::commit(const Image& image) {
  if (format_ == ImageFormat::png) {
    write_png(image, *output_, target_);
  } else {
    write_ppm(image, *output_);
  }
  output_->commit();
}

std::size_t encoding_peak_bytes(ImageFormat format, int width, int height) {
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const std::size_t image = 3 * pixels;
  if (format == ImageFormat::ppm) return image + (std::size_t{2} << 20);  // the chunk
  // stb_image_write: the filtered rows (a byte more per row), then deflate's output, which
  // grows by doubling (up to twice its final size, at most about the input's), while the rows
  // are still held; then the PNG copy of it.
  const std::size_t filtered = image + static_cast<std::size_t>(height);
  return image + filtered + 2 * filtered + (std::size_t{4} << 20);  // and its hash tables
}

void write_image(const Image& image, const std::filesystem::path& path) {
  PendingImageFile(path).commit(image);
}

}  // namespace sphray::render
