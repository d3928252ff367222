// The ranks' agreement (agreement.hpp): every rank learns the same answer, whichever rank holds
// the error or the differing value, and a call never leaves a rank waiting (ctest's timeout).
#include <gtest/gtest.h>
#include <mpi.h>

#include <string>
#include <vector>

#include "sphray/mpi/agreement.hpp"
#include "world.hpp"

namespace {

using sphray::mpi::test::rank;
using sphray::mpi::test::ranks;

using sphray::mpi::Disagreement;
using sphray::mpi::RankError;
using sphray::mpi::Setting;

TEST(MpiAgreement, FirstErrorIsTheLowestFailingRanksOnEveryRank) {
  const RankError none = sphray::mpi::first_error(MPI_COMM_WORLD, {});
  EXPECT_EQ(none.status, 0);
  EXPECT_EQ(none.rank, -1);
  // The last rank fails with status 2, and (with three ranks or more) rank 1 with status 1.
  RankError mine;
  if (rank() == ranks() - 1) mine = {2, "last rank's reason"};
  if (ranks() >= 3 && rank() == 1) mine = {1, "rank 1's reason"};
  const RankError first = sphray::mpi::first_error(MPI_COMM_WORLD, mine);
  if (ranks() >= 3) {
    EXPECT_EQ(first.rank, 1);
    EXPECT_EQ(first.status, 1);
    EXPECT_EQ(first.message, "rank 1's reason");
  } else {
    EXPECT_EQ(first.rank, ranks() - 1);
    EXPECT_EQ(first.status, 2);
    EXPECT_EQ(first.message, "last rank's reason");
  }
}

TEST(MpiAgreement, DisagreementsNameTheSettingsThatDifferWithTheirRange) {
  const auto r = static_cast<std::uint64_t>(rank());
  const Setting settings[] = {
      {"same", 7}, {"rank", 10 + r}, {"hash", 0xfffffffffffffff0u + r, false}};
  const std::vector<Disagreement> differing = sphray::mpi::disagreements(MPI_COMM_WORLD, settings);
  if (ranks() == 1) {
    EXPECT_TRUE(differing.empty());
    return;
  }
  ASSERT_EQ(differing.size(), 2u);
  EXPECT_EQ(differing[0].name, "rank");
  EXPECT_EQ(differing[0].min, 10u);
  EXPECT_EQ(differing[0].max, 10u + static_cast<std::uint64_t>(ranks() - 1));
  EXPECT_EQ(differing[1].max, 0xfffffffffffffff0u + static_cast<std::uint64_t>(ranks() - 1));
  EXPECT_EQ(sphray::mpi::describe(differing),
            "rank (10 to " + std::to_string(10 + ranks() - 1) + "), hash");
}

TEST(MpiAgreement, RanksThatPassDifferentListsStillMeetAndDisagree) {
  // Rank 0 passes one setting, the others two: the record has a fixed size, so the call is the
  // same collective on every rank.
  const Setting two[] = {{"a", 1}, {"b", 2}};
  const std::vector<Disagreement> differing = sphray::mpi::disagreements(
      MPI_COMM_WORLD, std::span<const Setting>(two, rank() == 0 ? 1 : 2));
  if (ranks() == 1) {
    EXPECT_TRUE(differing.empty());
    return;
  }
  ASSERT_FALSE(differing.empty());
  EXPECT_EQ(differing[0].name, "the number of settings");
}

TEST(MpiAgreement, TooManySettingsAreRefusedBeforeAnyCollective) {
  const std::vector<Setting> many(sphray::mpi::kMaxSettings + 1, Setting{"x", 1});
  EXPECT_THROW(sphray::mpi::disagreements(MPI_COMM_WORLD, many), std::length_error);
}

}  // namespace
