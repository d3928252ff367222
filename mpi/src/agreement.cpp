#include "sphray/mpi/agreement.hpp"

#include <array>
#include <stdexcept>

namespace sphray::mpi {

RankError first_error(MPI_Comm comm, const RankError& mine) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  // The lowest rank with an error, or ranks if none.
  int candidate = mine.status != 0 ? rank : ranks, first = ranks;
  MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == ranks) return {};
  // Its status and message travel from it to every rank.
  RankError error;
  error.rank = first;
  long long head[2] = {mine.status, static_cast<long long>(mine.message.size())};
  MPI_Bcast(head, 2, MPI_LONG_LONG, first, comm);
  error.status = static_cast<int>(head[0]);
  error.message =
      rank == first ? mine.message : std::string(static_cast<std::size_t>(head[1]), ' ');
  MPI_Bcast(error.message.data(), static_cast<int>(head[1]), MPI_CHAR, first, comm);
  return error;
}

std::vector<Disagreement> disagreements(MPI_Comm comm, std::span<const Setting> settings) {
  if (settings.size() > kMaxSettings)
    throw std::length_error("disagreements: more than kMaxSettings settings");
  // Slot 0 holds the number of settings, so that ranks that pass different lists disagree on it.
  // One MPI_MAX over each value and its complement gives the largest and the smallest.
  constexpr std::size_t kSlots = kMaxSettings + 1;
  std::array<std::uint64_t, 2 * kSlots> record{};
  record[0] = settings.size();
  for (std::size_t i = 0; i < settings.size(); ++i)
    record[i + 1] = settings[i].value;
  for (std::size_t i = 0; i < kSlots; ++i)
    record[kSlots + i] = ~record[i];
  MPI_Allreduce(MPI_IN_PLACE, record.data(), static_cast<int>(record.size()), MPI_UINT64_T, MPI_MAX,
                comm);
  std::vector<Disagreement> differing;
  const auto min_of = [&](std::size_t slot) { return ~record[kSlots + slot]; };
  if (min_of(0) != record[0]) differing.push_back({"the number of settings", min_of(0), record[0]});
  for (std::size_t i = 0; i < settings.size(); ++i) {
    if (min_of(i + 1) != record[i + 1])
      differing.push_back({settings[i].name, min_of(i + 1), record[i + 1], settings[i].shown});
  }
  return differing;
}

std::string describe(const std::vector<Disagreement>& differing) {
  std::string text;
  for (const Disagreement& d : differing) {
    if (!text.empty()) text += ", ";
    text += d.name;
    if (d.shown) text += " (" + std::to_string(d.min) + " to " + std::to_string(d.max) + ")";
  }
  return text;
}

}  // namespace sphray::mpi
