// The one temporary file a fatal signal should remove (see remove_temporaries_on_signals() in
// image_file.hpp). A slot of static storage that the signal handler reads without locking.
#pragma once

namespace sphray::render::detail {

/// Claims the slot for name in the folder dir_fd (kept open by the caller). Returns false if
/// another file holds it or name does not fit; that file is then only cleaned up by a later
/// run (its name is recognisable, see atomic_output.hpp).
bool arm_signal_cleanup(int dir_fd, const char* name) noexcept;
/// Releases the slot (the file was renamed or removed).
void disarm_signal_cleanup() noexcept;

}  // namespace sphray::render::detail
