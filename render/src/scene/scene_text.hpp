// Reading a scene file's bytes: from a path or from standard input ("-"), refused with a
// SceneError past a size cap, and never blocked forever by a FIFO that no process writes.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace sphray::render {

/// The scene argument that means standard input, and the name messages give it.
inline constexpr std::string_view kStandardInputName = "-";
inline constexpr std::string_view kStandardInputSource = "<stdin>";

/// The largest scene text read (about a million spheres of JSON); more is refused, so that
/// `-s /dev/zero` ends with a message instead of exhausting memory.
inline constexpr std::size_t kMaxSceneBytes = std::size_t{64} << 20;

/// How long a FIFO given by name may wait for its first byte. Opening a FIFO for reading
/// blocks until a writer opens it; the file is opened without blocking and then waited on for
/// this long, so a FIFO nobody writes to gives a message rather than a hang.
inline constexpr std::chrono::seconds kFifoFirstByteWait{5};

/// The bytes of file. Throws SceneError (a directory, unreadable, too large, a silent FIFO).
std::string read_scene_file(const std::filesystem::path& file);
/// The bytes of standard input, up to kMaxSceneBytes. Throws SceneError.
std::string read_scene_stdin();

}  // namespace sphray::render
