// Image files: PNG (stb_image_write) or PPM (P3, as Ray Tracing in One Weekend writes it),
// chosen by the extension, written to a temporary file beside the target and renamed over it
// only once complete, so a failed or interrupted render never leaves a half-written image nor
// destroys the one already there.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>

#include "sphray/render/renderer.hpp"

namespace sphray::render {

enum class ImageFormat { png, ppm };

/// The format the path's extension names (.png or .ppm, any case), or nothing.
std::optional<ImageFormat> image_format_for(const std::filesystem::path& path);

/// A file that cannot be created, written or renamed; what() is one line naming the path.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The temporary file for one output path, created at once (so an unwritable folder is found
/// before any rendering) and removed again unless commit() succeeded.
class PendingImageFile {
 public:
  /// Throws std::invalid_argument for an unknown extension, IoError if the temporary file
  /// cannot be created.
  explicit PendingImageFile(std::filesystem::path target);
  ~PendingImageFile();
  PendingImageFile(const PendingImageFile&) = delete;
  PendingImageFile& operator=(const PendingImageFile&) = delete;

  /// Writes image to the temporary file and renames it to the target. Throws IoError.
  void commit(const Image& image);

  const std::filesystem::path& target() const { return target_; }
  /// The temporary file's path (a signal handler may unlink it).
  const std::filesystem::path& temporary() const { return temporary_; }

 private:
  std::filesystem::path target_;
  std::filesystem::path temporary_;
  ImageFormat format_;
  int fd_ = -1;
};

/// PendingImageFile(path).commit(image).
void write_image(const Image& image, const std::filesystem::path& path);

}  // namespace sphray::render
