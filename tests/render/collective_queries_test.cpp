// The renderer over collective queries (RayQueries::collective, as sphray-mpi passes them), in
// one process: queries that count their calls stand in for the ranks. A frame traced in tile
// shares, each share's tiles together, must add up to the image render() makes with its own
// queries, byte for byte; a frame ends with one finish(); path mode over shares needs queries
// that take uneven calls.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "sphray/render/ray_queries.hpp"
#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render {
namespace {

// Answers from a tree over the scene's spheres, as a rank of an MPI job would over all of them.
class CountingQueries final : public RayQueries {
 public:
  CountingQueries(const Scene& scene, bool uneven) : bvh_(scene.spheres.view()), uneven_(uneven) {}
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const override {
    ++calls;
    largest = std::max(largest, rays.size());
    sphray::intersect(bvh_, rays, hits);
  }
  void occluded(std::span<const Ray> rays, std::span<bool> out) const override {
    ++calls;
    sphray::occluded(bvh_, rays, out);
  }
  bool collective() const override { return true; }
  bool uneven_calls() const override { return uneven_; }
  void finish() const override { ++finished; }

  mutable std::size_t calls = 0, finished = 0, largest = 0;

 private:
  SphereBVH bvh_;
  bool uneven_;
};

RenderOptions options_for(Mode mode) {
  RenderOptions o;
  o.mode = mode;
  o.width = 200;  // 13 x 10 tiles: more than a share traces at once in path mode
  o.height = 150;
  o.spp = 2;
  o.max_depth = 5;
  o.threads = 2;
  return o;
}

// The shares' images added pixel by pixel: each share leaves the others' tiles black.
Image shares_added(const Scene& scene, const RayQueries& queries, RenderOptions o, int count) {
  Image sum{o.width, o.height, std::vector<std::uint8_t>(3 * o.width * o.height, 0)};
  for (int index = 0; index < count; ++index) {
    o.share = TileShare{index, count};
    const Image part = render(scene, queries, o);
    for (std::size_t i = 0; i < sum.rgb.size(); ++i)
      sum.rgb[i] = static_cast<std::uint8_t>(sum.rgb[i] + part.rgb[i]);
  }
  return sum;
}

class CollectiveFrames : public ::testing::TestWithParam<Mode> {};

TEST_P(CollectiveFrames, SharesAddUpToTheImageOfOneProcess) {
  const Scene scene = make_preset("rtiow-final");
  const RenderOptions o = options_for(GetParam());
  const Image expected = render(scene, o);  // the renderer's own queries, on threads
  for (int count : {1, 2, 3}) {
    const CountingQueries queries(scene, /*uneven=*/true);
    const Image image = shares_added(scene, queries, o, count);
    EXPECT_EQ(image.rgb, expected.rgb) << count << " shares";
    EXPECT_EQ(queries.finished, static_cast<std::size_t>(count)) << "one finish() a frame";
  }
}

INSTANTIATE_TEST_SUITE_P(Modes, CollectiveFrames,
                         ::testing::Values(Mode::normals, Mode::shaded, Mode::path));

// A path-mode frame's calls are its group's rounds, each with the live paths of many tiles:
// far fewer than a call per tile and round, the 256 lanes of one tile far exceeded.
TEST(CollectiveFrames, PathModeTracesTilesTogether) {
  const Scene scene = make_preset("rtiow-final");
  RenderOptions o = options_for(Mode::path);
  o.spp = 1;
  const CountingQueries queries(scene, /*uneven=*/false);
  render(scene, queries, o);
  const std::size_t tiles = 13 * 10;
  EXPECT_LT(queries.calls, tiles);  // a tile alone makes at least one call
  EXPECT_GT(queries.largest, std::size_t{256} * 16);
}

// A share of the tiles makes its own number of calls (in path mode, its paths decide):
// refused with queries that need every process to make the same calls.
TEST_P(CollectiveFrames, SharesNeedUnevenCalls) {
  const Scene scene = make_preset("rtiow-final");
  RenderOptions o = options_for(GetParam());
  o.share = TileShare{0, 2};
  const CountingQueries queries(scene, /*uneven=*/false);
  EXPECT_THROW(render(scene, queries, o), std::invalid_argument);
  EXPECT_EQ(queries.calls, 0u);
}

// Listed shares of unequal sizes and shapes (the first 40 tiles and every fifth after them to
// one, the rest to the other) add up to the image too.
TEST_P(CollectiveFrames, ListedSharesAddUpToTheImageOfOneProcess) {
  const Scene scene = make_preset("rtiow-final");
  RenderOptions o = options_for(GetParam());
  const Image expected = render(scene, o);
  const std::size_t tiles = tile_count(o.width, o.height);
  std::vector<std::uint32_t> listed[2];
  for (std::uint32_t t = 0; t < tiles; ++t)
    listed[t < 40 || t % 5 == 0 ? 0 : 1].push_back(t);
  Image sum{o.width, o.height, std::vector<std::uint8_t>(expected.rgb.size(), 0)};
  const CountingQueries queries(scene, /*uneven=*/true);
  for (int index = 0; index < 2; ++index) {
    o.share = TileShare{index, 2, listed[index]};
    const Image part = render(scene, queries, o);
    for (std::size_t i = 0; i < sum.rgb.size(); ++i)
      sum.rgb[i] = static_cast<std::uint8_t>(sum.rgb[i] + part.rgb[i]);
  }
  EXPECT_EQ(sum.rgb, expected.rgb);
}

// A listed tile past the image's, or a listing out of order (a tile twice), is refused before
// any ray.
TEST_P(CollectiveFrames, ListedTilesOutsideTheImageOrOutOfOrderAreRefused) {
  const Scene scene = make_preset("rtiow-final");
  RenderOptions o = options_for(GetParam());
  const auto tiles = static_cast<std::uint32_t>(tile_count(o.width, o.height));
  ASSERT_EQ(tiles, 13u * 10u);
  for (const std::vector<std::uint32_t>& listed :
       {std::vector<std::uint32_t>{0, tiles}, {3, 2}, {4, 4}}) {
    o.share = TileShare{0, 2, listed};
    const CountingQueries queries(scene, /*uneven=*/true);
    EXPECT_THROW(render(scene, queries, o), std::invalid_argument);
    EXPECT_EQ(queries.calls, 0u);
  }
  o.share = TileShare{0, 2, {0, tiles - 1}};
  const CountingQueries queries(scene, /*uneven=*/true);
  EXPECT_NO_THROW(render(scene, queries, o));
}

}  // namespace
}  // namespace sphray::render
