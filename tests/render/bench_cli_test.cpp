// `sphray bench`, run as a process on tiny scenes with tiny time: its rows, its JSON output
// (read back and parsed here) and its refusals.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "command_run.hpp"
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

// The rows a small scene has, per ray kind: scalar and each instruction set's brute force, each
// instruction set's tree, and the stream of each but scalar.
std::size_t small_scene_rows() {
  const std::size_t isas = sphray::supported_isas().size();
  return isas + isas + (isas - 1);
}

TEST_F(BenchCli, TimesEveryRowAndWritesGoogleBenchmarkJson) {
  const Result r = run("bench -s three --rays both --seconds 0.001 -q --json " + path("r.json"));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("three, 3 spheres, 1 thread"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("camera rays"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("random rays"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scalar brute force"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Mrays/s"), std::string::npos) << r.out;

  const auto json = nlohmann::json::parse(sphray::test::read_bytes(path("r.json")));
  EXPECT_EQ(json.at("context").at("scene"), "three");
  EXPECT_EQ(json.at("context").at("spheres"), 3);
  EXPECT_EQ(json.at("context").at("sphray_bvh_isa"),
            std::string(sphray::isa_name(sphray::bvh_isa(3))));
  const auto& rows = json.at("benchmarks");
  std::size_t sphray_rows = 0, dispatched = 0;
  for (const auto& row : rows) {
    const std::string name = row.at("name");
    EXPECT_TRUE(name.starts_with("three/camera/") || name.starts_with("three/random/")) << name;
    EXPECT_TRUE(name.ends_with("/threads:1")) << name;
    EXPECT_GE(row.at("iterations").get<int>(), 1) << name;
    EXPECT_GT(row.at("real_time").get<double>(), 0.0) << name;
    EXPECT_EQ(row.at("time_unit"), "ms") << name;
    const double rate = row.at("items_per_second");
    const double rays = row.at("rays");
    // items per second is rays per pass over the time per pass.
    EXPECT_NEAR(rate, rays / (row.at("real_time").get<double>() / 1e3), 1e-6 * rate) << name;
    sphray_rows += name.find("/embree-") == std::string::npos;
    dispatched += row.value("label", "") == "dispatched";
  }
  EXPECT_EQ(sphray_rows, 2 * small_scene_rows());
  // Per ray kind: one brute force, the tree and the stream of the dispatched instruction set
  // (two if the tree's is scalar, which has no stream row).
  EXPECT_GE(dispatched, 2u * 2u);
  EXPECT_LE(dispatched, 2u * 3u);
}

TEST_F(BenchCli, LeavesBruteForceOutOnLargeScenes) {
  const Result r = run("bench -s random:4097 --rays camera --seconds 0 -q");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out.find(" brute force "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("scalar tree"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("random rays"), std::string::npos) << r.out;
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
  EXPECT_EQ(run("bench -s nosuch").status, 2);
}

TEST_F(BenchCli, AJsonFileThatCannotBeWrittenFailsTheRun) {
  const Result r = run("bench -s single --rays camera --seconds 0 -q --json " + path("no/r.json"));
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("cannot write"), std::string::npos) << r.out;
}

}  // namespace
