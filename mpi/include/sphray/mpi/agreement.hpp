// Agreement between the ranks of a job before they start work that only succeeds if they do it
// alike: whether any rank met an error (and which), and whether they hold the same input.
//
// Every rank of an MPI job runs the same collectives in the same order, with the same sizes, or
// the job hangs or corrupts memory. A rank whose input differs (a node-local file that differs
// between nodes, a file edited while the job starts, an MPMD launch with other options) or that
// met an error alone would leave the collectives; these functions let the ranks find out first,
// each in one or two small collectives, so that all of them stop together with the same status.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace sphray::mpi {

/// An error one rank met: status is the exit status it calls for (0: none), message one line.
struct RankError {
  int status = 0;
  std::string message;
  int rank = -1;  // first_error: the rank it came from
};

/// The error of the lowest rank whose status is non-zero, with its rank, known to every rank;
/// {0, "", -1} if no rank had one. Collective over comm.
RankError first_error(MPI_Comm comm, const RankError& mine);

/// A value every rank must hold alike, and its name for messages. A hash is not shown as a
/// number (shown = false); a count or an option is.
struct Setting {
  std::string name;
  std::uint64_t value = 0;
  bool shown = true;
};

/// A setting whose value differs between ranks: the smallest and largest value held.
struct Disagreement {
  std::string name;
  std::uint64_t min = 0, max = 0;
  bool shown = true;
};

/// The most settings one call compares: the record every rank reduces has a fixed size, so a
/// rank that passes other settings than the rest still makes the same collective call.
inline constexpr std::size_t kMaxSettings = 31;

/// The settings whose values differ between the ranks of comm, in the order given; the same
/// list on every rank that passes the same names (a rank that passes fewer settings than
/// another sees "the number of settings" differ, and only its own names). One MPI_Allreduce of a
/// fixed-size record. Throws std::length_error (before any collective) for more than
/// kMaxSettings settings.
std::vector<Disagreement> disagreements(MPI_Comm comm, std::span<const Setting> settings);

/// "what: a (1 to 2), b": one line for a message.
std::string describe(const std::vector<Disagreement>& differing);

/// FNV-1a, 64 bits, over bytes: a hash of input that the ranks compare instead of the input.
class Fnv1a {
 public:
  void add(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= p[i];
      hash_ *= 0x100000001b3ull;
    }
  }
  template <typename T>
  void add_value(const T& value) {
    add(&value, sizeof value);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace sphray::mpi
