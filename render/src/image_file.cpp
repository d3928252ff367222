#include "sphray/render/image_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
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

IoError io_error(const std::filesystem::path& path, const std::string& what, int error) {
  return IoError(path.string() + ": " + what + " (" + std::strerror(error) + ")");
}

// A name beside the target that no other process or render picks: the pid and a counter.
std::filesystem::path temporary_name(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name(".");
  name.append(target.filename().string());
  name.append(".").append(std::to_string(::getpid()));
  name.append(".").append(std::to_string(counter++)).append(".tmp");
  return target.parent_path() / name;
}

// Writes all of data to fd, or returns false with errno set.
bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t written = ::write(fd, p, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += written;
    size -= static_cast<std::size_t>(written);
  }
  return true;
}

// stb_image_write hands us the PNG in pieces; keep them until the whole file is known.
void append_to(void* context, void* data, int size) {
  auto* out = static_cast<std::string*>(context);
  out->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

std::string encode_png(const Image& image) {
  std::string bytes;
  int ok = stbi_write_png_to_func(append_to, &bytes, image.width, image.height, 3, image.rgb.data(),
                                  image.width * 3);
  if (ok == 0) bytes.clear();
  return bytes;
}

// P3 as the book writes it: a header, then one "r g b" line per pixel.
std::string encode_ppm(const Image& image) {
  char line[32];
  std::snprintf(line, sizeof line, "P3\n%d %d\n255\n", image.width, image.height);
  std::string text(line);
  text.reserve(text.size() + image.rgb.size() * 4);
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    std::snprintf(line, sizeof line, "%d %d %d\n", image.rgb[i], image.rgb[i + 1],
                  image.rgb[i + 2]);
    text.append(line);
  }
  return text;
}

}  // namespace

std::optional<ImageFormat> image_format_for(const std::filesystem::path& path) {
  std::string extension = lowercase(path.extension().string());
  if (extension == ".png") return ImageFormat::png;
  if (extension == ".ppm") return ImageFormat::ppm;
  return std::nullopt;
}

PendingImageFile::PendingImageFile(std::filesystem::path target) : target_(std::move(target)) {
  std::optional<ImageFormat> format = image_format_for(target_);
  if (!format) {
    throw std::invalid_argument(target_.string() +
                                ": expected an output file ending in .png or .ppm");
  }
  format_ = *format;
  temporary_ = temporary_name(target_);
  // 0666 less the umask, as the target would get if written directly.
  fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd_ < 0) throw io_error(target_, "cannot create the output file", errno);
}

PendingImageFile::~PendingImageFile() {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(temporary_.c_str());
  }
}

void PendingImageFile::commit(const Image& image) {
  std::string bytes = format_ == ImageFormat::png ? encode_png(image) : encode_ppm(image);
  if (bytes.empty()) throw IoError(target_.string() + ": cannot encode the image");
  if (!write_all(fd_, bytes.data(), bytes.size())) {
    throw io_error(target_, "cannot write the output file", errno);
  }
  int fd = fd_;
  fd_ = -1;  // from here on the destructor must not unlink a renamed file
  if (::close(fd) != 0) {
    int error = errno;
    ::unlink(temporary_.c_str());
    throw io_error(target_, "cannot write the output file", error);
  }
  if (::rename(temporary_.c_str(), target_.c_str()) != 0) {
    int error = errno;
    ::unlink(temporary_.c_str());
    throw io_error(target_, "cannot replace the output file", error);
  }
}

void write_image(const Image& image, const std::filesystem::path& path) {
  PendingImageFile(path).commit(image);
}

}  // namespace sphray::render
