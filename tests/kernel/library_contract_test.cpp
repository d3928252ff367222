// Issue 20's library findings: what the headers promise about bad instruction sets, moved-from
// trees and the lifetime of a SphereSoA's views.
#include <stdexcept>
#include <utility>

#include "test_support.hpp"

namespace sphray {
namespace {

SphereSoA three_spheres() {
  SphereSoA s;
  s.add({0, 0, -3}, 1.0f);
  s.add({2, 0, -5}, 1.0f);
  s.add({-2, 0, -5}, 1.0f);
  return s;
}

// bvh.hpp: std::invalid_argument for an instruction set that cannot run, which includes a value
// that is no Isa at all (isa_name's table lookup threw std::out_of_range).
TEST(LibraryContract, BvhRefusesAValueThatIsNoInstructionSet) {
  const SphereSoA spheres = three_spheres();
  EXPECT_THROW(SphereBVH(spheres.view(), static_cast<Isa>(7)), std::invalid_argument);
  EXPECT_THROW(SphereBVH(spheres.view(), static_cast<Isa>(-1)), std::invalid_argument);
}

void expect_empty_tree(const SphereBVH& bvh, Isa isa) {
  EXPECT_EQ(bvh.size(), 0u);
  EXPECT_EQ(bvh.memory_bytes(), 0u);
  EXPECT_EQ(bvh.isa(), isa);
  const Ray ray{{0, 0, 0}, {0, 0, -1}, 0.0f, 100.0f};
  const Hit hit = intersect(bvh, ray);
  EXPECT_FALSE(hit.found());
  EXPECT_EQ(hit.t, 100.0f);
  EXPECT_FALSE(occluded(bvh, ray));
}

// A moved-from tree dereferenced its released storage in size() (a segfault); it is now the
// empty tree of its instruction set, for move construction and move assignment alike.
TEST(LibraryContract, MovedFromBvhIsTheEmptyTree) {
  const SphereSoA spheres = three_spheres();
  const Ray ray{{0, 0, 0}, {0, 0, -1}, 0.0f, 100.0f};
  for (const EntryTable* k : test::runnable_kernels()) {
    SCOPED_TRACE(isa_name(k->isa));
    SphereBVH source(spheres.view(), k->isa);
    SphereBVH moved(std::move(source));
    expect_empty_tree(source, k->isa);  // NOLINT(bugprone-use-after-move): the point
    EXPECT_EQ(moved.size(), 3u);
    EXPECT_EQ(intersect(moved, ray).id, 0u);
    EXPECT_EQ(intersect(moved, ray).t, 2.0f);

    SphereBVH assigned;
    assigned = std::move(moved);
    expect_empty_tree(moved, k->isa);  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(intersect(assigned, ray).id, 0u);

    // Refit the moved-from tree: an empty view is its own count, three spheres are not.
    EXPECT_NO_THROW(moved.refit(SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}));
    EXPECT_THROW(moved.refit(spheres.view()), std::invalid_argument);
    expect_empty_tree(moved, k->isa);
  }
}

// spheres.hpp: add() may reallocate and so invalidate earlier views; reserve() first keeps them.
TEST(LibraryContract, ReserveKeepsViewsAcrossAddsAndGrowthMovesThem) {
  SphereSoA reserved;
  reserved.reserve(100);
  const SphereView before = reserved.view();
  for (int i = 0; i < 100; ++i)
    reserved.add({0, 0, float(i)}, 1.0f);
  EXPECT_EQ(reserved.view().cx, before.cx);
  EXPECT_EQ(reserved.view().radius, before.radius);

  SphereSoA growing;
  growing.add({0, 0, 0}, 1.0f);
  const std::size_t capacity = growing.capacity();
  const SphereView first = growing.view();
  while (growing.size() <= capacity)
    growing.add({0, 0, 1}, 1.0f);
  EXPECT_GT(growing.capacity(), capacity);
  EXPECT_NE(growing.view().cx, first.cx);  // the documented reallocation: first is stale
}

}  // namespace
}  // namespace sphray
