// Image files: PNG (stb_image_write) or PPM (P3, as Ray Tracing in One Weekend writes it),
// chosen by the extension, written to a temporary file beside the target and renamed over it
// only once complete, so a failed or interrupted render never leaves a half-written image nor
// destroys the one already there. The rules for existing outputs (modes, owners, symbolic and
// hard links, read-only files) are in docs/robustness.md, "The output file".
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>

#include "sphray/render/renderer.hpp"

namespace sphray::render {

namespace detail {
class AtomicOutput;
}

enum class ImageFormat { png, ppm };

/// The format the path's extension names (.png or .ppm, any case), or nothing.
std::optional<ImageFormat> image_format_for(const std::filesystem::path& path);

/// A file that cannot be created, written or renamed; what() is one line naming the path.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An output path refused before anything is written: a directory, a dangling symbolic link,
/// a special file, a name that cannot be looked up (too long, a link loop, a folder that
/// cannot be searched), or a read-only file. what() is one line naming the path.
class OutputRefused : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The temporary file for one output path, created at once (so an unwritable folder is found
/// before any rendering) and removed again unless commit() succeeded.
class PendingImageFile {
 public:
  /// Throws std::invalid_argument for an unknown extension, OutputRefused for an output that
  /// cannot or may not be replaced (a read-only file unless replace_read_only), IoError if the
  /// temporary file cannot be created.
  explicit PendingImageFile(std::filesystem::path target, bool replace_read_only = false);
  ~PendingImageFile();
  PendingImageFile(const PendingImageFile&) = delete;
  PendingImageFile& operator=(const PendingImageFile&) = delete;

  /// Writes image to the temporary file and renames it to the target. Throws IoError.
  void commit(const Image& image);

  const std::filesystem::path& target() const { return target_; }

 private:
  std::filesystem::path target_;
  ImageFormat format_;
  std::unique_ptr<detail::AtomicOutput> output_;
};

/// Bytes of memory writing a width x height image in format may take at its peak, the image
/// itself included (the PNG encoder's worst case: incompressible pixels).
std::size_t encoding_peak_bytes(ImageFormat format, int width, int height);

/// Installs handlers that remove a PendingImageFile's named temporary file on every signal
/// that ends a process and can be caught (SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGPIPE, SIGALRM,
/// SIGUSR1, SIGUSR2, SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF, SIGIO, SIGPWR), then die of the
/// signal as before. A signal whose disposition is not the default (ignored, as nohup leaves
/// SIGHUP, or handled by the program) is left as it is. For programs, not libraries: it
/// changes process-wide state.
void remove_temporaries_on_signals();

/// PendingImageFile(path).commit(image).
void write_image(const Image& image, const std::filesystem::path& path);

}  // namespace sphray::render
