// How the `sphray` command's subcommands end when they fail: one line on stderr and an exit
// status that tells a refusal from a failure (docs/robustness.md).
#pragma once

#include <string>

namespace sphray::render {

/// A failure while working: I/O, memory.
inline constexpr int kExitIo = 1;
/// A refusal: a bad scene or particle file, an argument or output that may not be used.
inline constexpr int kExitUsage = 2;

/// "sphray: message" on stderr.
void report(const std::string& message);

/// Called in a catch handler: reports the exception being handled in one line and returns its
/// exit status; a std::bad_alloc is reported as out_of_memory. Exceptions it does not know
/// (a bug) go on to the caller, whose handler says "unexpected error".
int report_failure(const std::string& out_of_memory);

}  // namespace sphray::render
