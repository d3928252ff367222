// `sphray bench`, run as a process on tiny scenes with tiny time: its rows, its JSON output
// (read back and parsed here) and its refusals.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/bench_crossings.hpp"
#include "bench/bench_rays.hpp"
#include "bench/bench_report.hpp"
#include "command_run.hpp"
#include "sphray/render/scene.hpp"
#include "sphray/sphray.hpp"
#include "test_files.hpp"

namespace {

namespace fs = std::filesystem;

using Result = sphray::test::CommandResult;

Result run(const std::string& args) {
  return sphray::test::run_sphray(args);
}

class BenchCli : public sphray::test::ScratchDirTest {
 protected:
  BenchCli() : ScratchDirTest("sphray-bench-") {}
};

// The rows a small scene has, per ray kind: scalar and each instruction set's brute force, the
// rays across the lanes of each but scalar, the stream on the spheres, each instruction set's
// tree, and the stream of each but scalar.
std::size_t small_scene_rows() {
  const std::size_t isas = sphray::supported_isas().size();
  return isas + (isas - 1) + 1 + isas + (isas - 1);
}

TEST_F(BenchCli, TimesEveryRowAndWritesGoogleBenchmarkJson) {
  const Result r =
      run("bench -s three --rays both --seconds 0.001 --repetitions 2 -q --json " + path("r.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("three, 3 spheres, 1 thread, 0.001 s per row in 2 repetitions"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("camera rays"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("random rays"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scalar brute force"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Mrays/s  (min-max)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("by CPU time"), std::string::npos) << r.out;

  const auto json = nlohmann::json::parse(sphray::test::read_bytes(path("r.json")));
  EXPECT_EQ(json.at("context").at("scene"), "three");
  EXPECT_EQ(json.at("context").at("spheres"), 3);
  EXPECT_EQ(json.at("context").at("repetitions"), 2);
  EXPECT_EQ(json.at("context").at("sphray_bvh_isa"),
            std::string(sphray::isa_name(sphray::bvh_isa(3))));
  const auto& rows = json.at("benchmarks");
  std::size_t sphray_rows = 0, dispatched = 0, medians = 0;
  for (const auto& row : rows) {
    const std::string name = row.at("name");
    EXPECT_TRUE(name.starts_with("three/camera/") || name.starts_with("three/random/")) << name;
    EXPECT_EQ(row.at("repetitions"), 2) << name;
    EXPECT_EQ(row.at("time_unit"), "ms") << name;
    if (row.at("run_type") == "aggregate") {
      // Google Benchmark's aggregates: NAME_mean and so on, after the repetitions.
      const std::string aggregate = row.at("aggregate_name");
      EXPECT_TRUE(name.ends_with("/threads:1_" + aggregate)) << name;
      EXPECT_EQ(row.at("run_name").get<std::string>() + "_" + aggregate, name);
      medians += aggregate == "median";
      continue;
    }
    EXPECT_EQ(row.at("run_type"), "iteration") << name;
    EXPECT_TRUE(name.ends_with("/threads:1")) << name;
    EXPECT_GE(row.at("iterations").get<int>(), 1) << name;
    EXPECT_GT(row.at("real_time").get<double>(), 0.0) << name;
    const double rate = row.at("items_per_second");
    const double rays = row.at("rays");
    // items per second is rays per pass over the time per pass.
    EXPECT_NEAR(rate, rays / (row.at("real_time").get<double>() / 1e3), 1e-6 * rate) << name;
    if (row.at("repetition_index") != 0) continue;
    sphray_rows += name.find("/embree-") == std::string::npos;
    dispatched += row.value("label", "") == "dispatched";
  }
  EXPECT_EQ(sphray_rows, 2 * small_scene_rows());
  EXPECT_GE(medians, 2 * small_scene_rows());
  // Per ray kind: one brute force, the stream on the spheres, the tree and the stream of the
  // dispatched instruction set (three if the tree's is scalar, which has no stream row).
  EXPECT_GE(dispatched, 2u * 3u);
  EXPECT_LE(dispatched, 2u * 4u);
}

// The run says up front how long it should take, and at the end how long it took and which of
// sphray's calls was fastest, in plain words.
TEST_F(BenchCli, EstimatesTheRunAndRecommendsACall) {
  const Result r = run("bench -s three --rays camera --seconds 0 -q");
  ASSERT_EQ(r.status, 0) << r.out;
  const std::size_t estimate = r.out.find(" rows to time (");
  ASSERT_NE(estimate, std::string::npos) << r.out;
  EXPECT_LT(estimate, r.out.find("camera rays")) << r.out;  // before the first row
  EXPECT_NE(r.out.find("fastest for camera rays: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("took "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(estimated: "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("of the rays)"), std::string::npos) << r.out;  // the old cryptic notes
  EXPECT_EQ(r.out.find("(tree* "), std::string::npos) << r.out;
}

// On a terminal, stderr names the row in hand, of how many, with the time left; -q silences it.
TEST_F(BenchCli, ShowsTheRowInHandAndTheTimeLeftOnATerminal) {
  const Result r = sphray::test::run_sphray_on_terminal("bench -s three --rays camera --seconds 0");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("[1/"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scalar brute force: checking ... "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" left"), std::string::npos) << r.out;
  const Result quiet =
      sphray::test::run_sphray_on_terminal("bench -s three --rays camera --seconds 0 -q");
  ASSERT_EQ(quiet.status, 0) << quiet.out;
  EXPECT_EQ(quiet.out.find("[1/"), std::string::npos) << quiet.out;
}

// Every row left out says so and why, on the console and in the JSON.
TEST_F(BenchCli, SaysWhyItSkipsBruteForceOnLargeScenes) {
  const Result r = run("bench -s random:4097 --rays camera --seconds 0 --repetitions 1 -q --json " +
                       path("r.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  const std::string reason =
      " skipped: brute force is timed up to 4096 spheres, this scene has 4097";
  std::size_t lines = 0;
  for (std::size_t at = r.out.find(reason); at != std::string::npos;
       at = r.out.find(reason, at + 1))
    ++lines;
  // scalar, each instruction set's per ray and across its lanes, and the stream on the spheres
  const std::size_t brute_rows = 2 * sphray::supported_isas().size();
  EXPECT_EQ(lines, brute_rows) << r.out;
  EXPECT_NE(r.out.find("scalar brute force"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scalar tree"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("random rays"), std::string::npos) << r.out;
  const auto json = nlohmann::json::parse(sphray::test::read_bytes(path("r.json")));
  std::size_t skipped = 0;
  for (const auto& row : json.at("context").at("skipped"))
    skipped += row.at("reason").get<std::string>().starts_with("brute force is timed up to");
  EXPECT_EQ(skipped, brute_rows);
  for (const auto& row : json.at("benchmarks"))
    EXPECT_EQ(row.at("name").get<std::string>().find("brute-force"), std::string::npos);
}

namespace bench = sphray::render::bench;

TEST(BenchReport, WarnsWhenTheLoadAverageSaysTheMachineIsBusy) {
  const std::string busy = bench::load_warning(3.7, 2, 1);
  EXPECT_NE(busy.find("warning: the machine is busy (load average 3.70"), std::string::npos)
      << busy;
  EXPECT_NE(busy.find("CPU time"), std::string::npos) << busy;
  EXPECT_EQ(bench::load_warning(0.4, 2, 1), "");
  EXPECT_EQ(bench::load_warning(1.2, 4, 2), "");
  EXPECT_NE(bench::load_warning(1.2, 4, 4), "");  // every core wanted, one already taken
}

TEST(BenchReport, EstimateCountsEachTimedRowsSeconds) {
  EXPECT_DOUBLE_EQ(bench::estimate_seconds(28, 0.3), 28 * 0.3);
  EXPECT_DOUBLE_EQ(bench::estimate_seconds(0, 0.3), 0.0);
}

TEST(BenchReport, RecommendsTheFastestDefaultCallAndSaysWhenItIsWithinTheSpread) {
  std::vector<bench::Measured> rows = {
      {"avx512 brute force", true, true, false, true, 8.9e6, 8.8e6, 9.0e6},
      {"avx512 tree", true, false, false, true, 11.9e6, 11.6e6, 12.2e6},
      {"avx512 stream", true, false, true, true, 12.2e6, 12.1e6, 12.4e6},
      {"avx2 stream", false, false, true, true, 12.3e6, 12.0e6, 12.5e6},
      {"embree rtcIntersect16", false, false, false, false, 30e6, 29e6, 31e6},
  };
  std::string text = bench::recommendation(rows, "camera");
  EXPECT_EQ(text.rfind("fastest for camera rays: the stream call on a tree, "
                       "sphray::intersect(tree, rays, hits), 12.20 Mrays/s (avx512 stream)\n",
                       0),
            0u)
      << text;
  EXPECT_NE(text.find("sphray::intersect(tree, ray): 1.03x slower, within the spread"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("sphray::intersect(spheres, ray): 1.37x slower\n"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("faster still"), std::string::npos) << text;  // within the spread
  EXPECT_EQ(text.find("embree"), std::string::npos) << text;        // not one of sphray's calls
  rows[3].median = 14e6;
  rows[3].min = 13.5e6;
  text = bench::recommendation(rows, "camera");
  EXPECT_NE(text.find("faster still here: a tree laid out for avx2 (avx2 stream), built as "
                      "SphereBVH(spheres, sphray::Isa::avx2): 1.15x as fast"),
            std::string::npos)
      << text;
  EXPECT_EQ(bench::recommendation({rows.back()}, "camera"), "");
  // The stream on the spheres themselves (few spheres: the rays across the lanes).
  rows.push_back({"brute force stream", true, true, true, true, 40e6, 39e6, 41e6});
  text = bench::recommendation(rows, "camera");
  EXPECT_EQ(text.rfind("fastest for camera rays: the stream call on the spheres, "
                       "sphray::intersect(spheres, rays, hits), 40.00 Mrays/s",
                       0),
            0u)
      << text;
}

TEST_F(BenchCli, ASceneFileErrorSaysWhereAndExitsWithTwo) {
  sphray::test::write_text(path("bad.json"),
                           "{\"spheres\": [\n  {\"center\": [0,0,-1], \"radius\": -0.5}\n]}");
  const Result r = run("bench -s " + path("bad.json") + " --seconds 0");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("sphray: " + path("bad.json") +
                       ":2:34: expected \"radius\" to be positive, got -0.5"),
            std::string::npos)
      << r.out;
}

TEST_F(BenchCli, RefusesUnknownRayKindsAndThreadCounts) {
  EXPECT_EQ(run("bench -s three --rays sideways").status, 2);
  EXPECT_EQ(run("bench -s three --threads 0").status, 2);
  EXPECT_EQ(run("bench -s three --seconds -1").status, 2);
  EXPECT_EQ(run("bench -s three --repetitions 0").status, 2);
  EXPECT_EQ(run("bench -s nosuch").status, 2);
}

// Refused before any row is timed: nothing measured, the reason named, the old file kept.
TEST_F(BenchCli, AJsonFileThatCannotBeWrittenIsRefusedBeforeTiming) {
  fs::create_directory(path("dir"));
  struct Case {
    std::string json;
    int status;
    std::string reason;
  };
  for (const Case& c : {Case{path("no/r.json"), 1, "No such file or directory"},
                        Case{path("dir"), 2, "directory"}, Case{"/dev/full", 2, "/dev/full"}}) {
    const Result r = run("bench -s single --rays camera --seconds 0 -q --json " + c.json);
    EXPECT_EQ(r.status, c.status) << c.json << ": " << r.out;
    EXPECT_NE(r.out.find("sphray: " + c.json), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(c.reason), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("rows to time"), std::string::npos) << r.out;  // nothing timed
  }
  sphray::test::write_text(path("old.json"), "the previous results");
  fs::permissions(path("old.json"), fs::perms::owner_read | fs::perms::group_read);
  const Result refused =
      run("bench -s single --rays camera --seconds 0 -q --json " + path("old.json"));
  EXPECT_EQ(refused.status, 2) << refused.out;
  EXPECT_NE(refused.out.find("read-only (use --force"), std::string::npos) << refused.out;
  EXPECT_EQ(sphray::test::read_bytes(path("old.json")), "the previous results");
  const Result forced =
      run("bench -s single --rays camera --seconds 0 -q --force --json " + path("old.json"));
  EXPECT_EQ(forced.status, 0) << forced.out;
  EXPECT_NO_THROW(nlohmann::json::parse(sphray::test::read_bytes(path("old.json"))));
}

// --query every-hit: sphray's every-crossing rows, checked against the scalar reference, and
// where the build has Embree its multi-hit filters, checked against sphray's lists on every ray.
TEST_F(BenchCli, EveryHitRowsAreCheckedAndTimed) {
  const Result r =
      run("bench -s random:512 --query every-hit --rays random --seconds 0.001 "
          "--repetitions 1 -q --json " +
          path("r.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("random rays (262144 random rays, 262144 rays), every crossing"),
            std::string::npos)
      << r.out;
  for (const char* row : {"tree count_hits", "tree intersect_all16", "tree intersect_nearest16"})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
  const bool embree = r.out.find("Embree: not in this build") == std::string::npos;
  const auto json = nlohmann::json::parse(sphray::test::read_bytes(path("r.json")));
  std::size_t rows = 0;
  for (const auto& row : json.at("benchmarks"))
    rows += row.at("run_type") == "iteration";
  EXPECT_EQ(rows, embree ? 5u : 3u);
  if (!embree) return;
  EXPECT_NE(r.out.find("embree filter count"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("embree filter all16"), std::string::npos) << r.out;
  // Each filter row names the sphray row with its answer, and says it was checked on every ray
  // (a disagreement would have failed the run).
  EXPECT_NE(r.out.find("tree count_hits is "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tree intersect_all16 is "), std::string::npos) << r.out;
  std::size_t agreed = 0;
  for (std::size_t at = 0; (at = r.out.find("checked on all 262144 rays", at)) != std::string::npos;
       ++at)
    ++agreed;
  EXPECT_EQ(agreed, 2u) << r.out;
}

// The checks have teeth: a row that loses one crossing, or reports one too many, is caught.
TEST(BenchCrossings, ARowThatMissesACrossingDisagrees) {
  using namespace sphray::render::bench;
  const sphray::render::Scene scene = sphray::render::load_scene_or_preset("random:512");
  const RaySet set = make_ray_set(scene, RayKind::random);
  const std::vector<CrossingRow> rows = sphray_crossing_rows();
  const CrossingRow& all = rows[1];
  ASSERT_EQ(all.name, "tree intersect_all16");
  const sphray::SphereView spheres = scene.spheres.view();
  const CrossingTrace right = all.prepare(spheres);
  EXPECT_EQ(check_crossing_row(all, right, set, spheres, right).mismatch, "");
  for (const int change : {-1, +1}) {
    const CrossingTrace wrong = [&right, change](std::span<const sphray::Ray> rays,
                                                 std::span<std::size_t> totals,
                                                 std::span<sphray::Hit> lists) {
      right(rays, totals, lists);
      for (std::size_t& total : totals)
        if (total > 0) total = static_cast<std::size_t>(static_cast<long>(total) + change);
    };
    // As sphray's row, on the sample, against the scalar reference.
    EXPECT_NE(check_crossing_row(all, wrong, set, spheres, right).mismatch, "") << change;
    // As another library's row, on every ray, against sphray's.
    CrossingRow other = all;
    other.sphray = false;
    const CrossingCheck check = check_crossing_row(other, wrong, set, spheres, right);
    EXPECT_NE(check.mismatch.find("in the chunk from ray 0"), std::string::npos) << check.mismatch;
  }
}

}  // namespace
