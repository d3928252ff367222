// sphray-mpi-simulate: one process plays P ranks of a routed query, to count what the ranks
// would do at scales this machine cannot run: the rays each rank traces, the records sent
// between ranks and the exchanges, for P = 16 to 2048 (docs/distributed.md, the model).
//
//   sphray-mpi-simulate random:4194304 --ranks 16,64,256,1024,2048 --rays 262144
//
// The scene is split as sphray-mpi splits it (spatial_shares), each share gets its tree, and
// every ray of the benchmark's view walks the regions in the order the routed queries use
// (next_region), bounded by its nearest hit so far as they are. Each ray's answer is checked
// against one tree over the whole scene (exit 1 if any differs). No MPI: nothing here is timed
// or sent.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "sphray/mpi/regions.hpp"
#include "sphray/mpi/spatial_split.hpp"
#include "sphray/render/scene.hpp"
#include "view_rays.hpp"

namespace {

using namespace sphray;

// One simulated rank: its tree over its share, in ascending global id as DistributedScene
// keeps it, and the global ids.
struct SimulatedRank {
  std::vector<std::uint32_t> ids;
  SphereBVH tree;
};

struct Tally {
  std::vector<std::uint64_t> traced;   // per rank
  std::vector<std::uint64_t> crossed;  // per rank: rays whose whole segment crosses its region
  std::uint64_t sent = 0;              // records between different ranks: rays and answers
  std::uint64_t waves = 0;             // the exchanges the busiest batch needs
  std::uint64_t wrong = 0;             // answers unlike the whole scene's tree
};

// Ray `ray` of owner `owner`, walked through its regions as intersect_routed walks it.
void walk(const std::vector<SimulatedRank>& ranks, std::span<const mpi::RegionBox> regions,
          const SphereBVH& whole, const Ray& ray, std::size_t owner, Tally& tally) {
  Hit best{ray.tmax, kNoHit};
  std::size_t holder = owner, visits = 0;
  mpi::RegionKey at;
  for (;;) {
    at = mpi::next_region(regions, ray, best.found() ? best.t : ray.tmax, at);
    if (at.region < 0) break;
    const auto region = static_cast<std::size_t>(at.region);
    tally.sent += region != holder ? 1 : 0;
    holder = region;
    ++visits;
    ++tally.traced[region];
    const Hit local = intersect(ranks[region].tree, mpi::bounded_by(ray, best));
    if (local.found()) mpi::keep_nearer(best, {local.t, ranks[region].ids[local.id]});
  }
  tally.sent += holder != owner ? 1 : 0;  // the answer goes home
  // Shared batches search every region the segment crosses, with no bound from the others.
  for (mpi::RegionKey crossing = mpi::next_region(regions, ray, ray.tmax, {}); crossing.region >= 0;
       crossing = mpi::next_region(regions, ray, ray.tmax, crossing))
    ++tally.crossed[static_cast<std::size_t>(crossing.region)];
  // Wave k carries the k-th visits; one more brings answers home from another rank.
  tally.waves = std::max<std::uint64_t>(tally.waves, visits + (holder != owner ? 1 : 0));
  const Hit expected = intersect(whole, ray);
  if (expected.id != best.id ||
      !(expected.t == best.t || (std::isnan(expected.t) && std::isnan(best.t))))
    ++tally.wrong;
}

// Prints the table's row for `ranks` ranks; returns the answers unlike one tree's.
std::uint64_t simulate(const SphereSoA& spheres, const SphereBVH& whole, int ranks,
                       std::uint64_t rays, int axis, bool planes) {
  const auto shares = planes ? mpi::plane_shares(spheres.view(), ranks)
                             : mpi::spatial_shares(spheres.view(), ranks);
  std::vector<SimulatedRank> simulated(shares.size());
  std::vector<mpi::RegionBox> regions(shares.size());
  for (std::size_t r = 0; r < shares.size(); ++r) {
    SphereSoA mine;
    mine.reserve(shares[r].size());
    for (std::uint32_t id : shares[r])
      mine.add(spheres.center(id), spheres.radius(id), spheres.mask(id));
    simulated[r].ids = shares[r];
    simulated[r].tree = SphereBVH(mine.view());
    regions[r] = mpi::region_box(mine.view());
  }
  const auto [lo, hi] = mpi::tools::box_of(spheres);
  const auto side = static_cast<std::uint64_t>(std::ceil(std::sqrt(static_cast<double>(rays))));
  Tally tally;
  tally.traced.assign(shares.size(), 0);
  tally.crossed.assign(shares.size(), 0);
  const auto p = static_cast<std::uint64_t>(ranks);
  for (std::uint64_t i = 0; i < rays; ++i) {
    const Ray ray = mpi::tools::view_ray(i, side, lo, hi, axis, false);
    walk(simulated, regions, whole, ray, static_cast<std::size_t>(i * p / rays), tally);
  }
  std::uint64_t traced = 0, busiest = 0;
  for (std::uint64_t t : tally.traced) {
    traced += t;
    busiest = std::max(busiest, t);
  }
  const std::uint64_t most_crossed = *std::max_element(tally.crossed.begin(), tally.crossed.end());
  const double n = static_cast<double>(rays);
  const double mean = static_cast<double>(traced) / static_cast<double>(p);
  std::printf("| %d | %zu | %.3f | %.3f | %.2f | %.3f | %llu | %.3f | %llu |\n", ranks,
              spheres.size() / shares.size(), static_cast<double>(traced) / n,
              static_cast<double>(busiest) / n,
              mean > 0 ? static_cast<double>(busiest) / mean : 0.0,
              static_cast<double>(tally.sent) / n, static_cast<unsigned long long>(tally.waves),
              static_cast<double>(most_crossed) / n, static_cast<unsigned long long>(tally.wrong));
  return tally.wrong;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "sphray-mpi-simulate: one process plays P ranks of a routed query and counts "
      "their work and messages",
      "sphray-mpi-simulate"};
  std::string scene_name;
  std::vector<int> rank_counts{16, 64, 256, 1024, 2048};
  std::uint64_t rays = 1 << 18;
  std::string from = "z";
  std::string split = "morton";
  app.add_option("scene", scene_name, "A preset (random:N) or a .json scene")->required();
  app.add_option("--ranks", rank_counts, "The rank counts to play")
      ->delimiter(',')
      ->check(CLI::Range(1, 1 << 20));
  app.add_option("--rays", rays, "Rays of the view, dealt to the ranks in equal runs")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 30))
      ->capture_default_str();
  app.add_option("--from", from, "The axis the view looks along, from its + side")
      ->check(CLI::IsMember({"x", "y", "z"}))
      ->capture_default_str();
  app.add_option("--split", split,
                 "morton: equal runs of a Morton curve (sphray-mpi's split); planes: a k-d "
                 "split by count")
      ->check(CLI::IsMember({"morton", "planes"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const render::Scene scene = render::load_scene_or_preset(scene_name);
    const SphereSoA& spheres = scene.spheres;
    const SphereBVH whole(spheres.view());
    std::printf(
        "| ranks | spheres a rank | visits a ray | busiest rank's visits a ray | "
        "busiest over mean | records sent a ray | waves | shared batches: busiest rank's "
        "crossings a ray | answers unlike one tree |\n"
        "|---|---|---|---|---|---|---|---|---|\n");
    std::uint64_t wrong = 0;
    for (int ranks : rank_counts) {
      if (static_cast<std::size_t>(ranks) > spheres.size()) {
        std::fprintf(stderr, "sphray-mpi-simulate: %d ranks: more ranks than spheres (%zu)\n",
                     ranks, spheres.size());
        return 2;
      }
      wrong += simulate(spheres, whole, ranks, rays, mpi::tools::axis_of(from), split == "planes");
    }
    if (wrong > 0) {
      std::fprintf(stderr, "sphray-mpi-simulate: %llu routed answers differ from one tree's\n",
                   static_cast<unsigned long long>(wrong));
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sphray-mpi-simulate: %s\n", e.what());
    return 2;
  }
  return 0;
}
