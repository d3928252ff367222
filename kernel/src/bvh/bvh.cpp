// SphereBVH: owns the built arrays and forwards queries to the kernel it was laid out for.
#include "sphray/bvh.hpp"

#include <stdexcept>
#include <string>

#include "bvh/build.hpp"
#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"
#include "storage/ray_columns.hpp"

namespace sphray {

BuildCancelled::BuildCancelled() : std::runtime_error("sphray::SphereBVH: build cancelled") {}

struct SphereBVH::Storage {
  detail::BvhArrays arrays;
  detail::BvhData data;  // views of arrays

  static std::unique_ptr<Storage> build(SphereView spheres, const detail::EntryTable& entries,
                                        const BvhBuildOptions& options,
                                        const BuildProgress& progress = {}) {
    auto storage = std::make_unique<Storage>();
    storage->arrays = detail::build_bvh(spheres, entries.bvh_width, options, progress);
    storage->data = storage->arrays.data();
    return storage;
  }
};

namespace {

using detail::EntryTable;

// The number of Isa enumerators: a value cast from anything else names no instruction set.
constexpr std::size_t kIsaCount = 5;

const EntryTable& entries_for(Isa isa) {
  const auto index = static_cast<std::size_t>(isa);
  if (index >= kIsaCount) {
    throw std::invalid_argument("sphray::SphereBVH: " + std::to_string(index) +
                                " is not an instruction set");
  }
  const EntryTable* k = detail::find_entries(isa);
  if (k == nullptr)
    throw std::invalid_argument("sphray::SphereBVH: instruction set " + std::string(isa_name(isa)) +
                                " cannot run here");
  return *k;
}

}  // namespace

SphereBVH::SphereBVH() : SphereBVH(SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}) {}

SphereBVH::SphereBVH(SphereView spheres, BvhBuildOptions options)
    : SphereBVH(spheres, bvh_isa(spheres.count), options) {}

SphereBVH::SphereBVH(SphereView spheres, Isa isa, BvhBuildOptions options)
    : entries_(&entries_for(isa)) {
  storage_ = Storage::build(spheres, *entries_, options);
}

SphereBVH::SphereBVH(SphereView spheres, BvhBuildOptions options, const BuildProgress& progress)
    : entries_(&entries_for(bvh_isa(spheres.count))) {
  storage_ = Storage::build(spheres, *entries_, options, progress);
}

// A moved-from tree keeps its kernel and loses its storage: it reads as the empty tree.
SphereBVH::SphereBVH(SphereBVH&& other) noexcept = default;
SphereBVH& SphereBVH::operator=(SphereBVH&& other) noexcept = default;
SphereBVH::~SphereBVH() = default;

void SphereBVH::refit(SphereView spheres) {
  if (!storage_)
    storage_ = Storage::build({nullptr, nullptr, nullptr, nullptr, 0, 0}, *entries_, {});
  detail::refit_bvh(storage_->arrays, spheres);
  storage_->data = storage_->arrays.data();  // the leaf overlap changed
}

std::size_t SphereBVH::size() const {
  return detail::BvhAccess::data(*this).count;
}

Isa SphereBVH::isa() const {
  return entries_->isa;
}

std::size_t SphereBVH::memory_bytes() const {
  return detail::BvhAccess::data(*this).memory_bytes;
}

// The empty tree's arrays: no nodes, no spheres. Every query misses it (count 0 takes the
// scalar walk, which visits nothing).
constexpr detail::BvhData kEmptyTree{};

const detail::BvhData& detail::BvhAccess::data(const SphereBVH& bvh) {
  return bvh.storage_ ? bvh.storage_->data : kEmptyTree;
}

const EntryTable& detail::BvhAccess::entries(const SphereBVH& bvh) {
  return *bvh.entries_;
}

Hit intersect(const SphereBVH& bvh, const Ray& ray) {
  using A = detail::BvhAccess;
  return A::entries(bvh).bvh_intersect(A::data(bvh), ray);
}

bool occluded(const SphereBVH& bvh, const Ray& ray) {
  using A = detail::BvhAccess;
  return A::entries(bvh).bvh_occluded(A::data(bvh), ray);
}

void intersect(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  using A = detail::BvhAccess;
  A::entries(bvh).bvh_intersect_stream(A::data(bvh), rays.data(), hits.data(), rays.size());
}

void intersect(const SphereBVH& bvh, const RayArrays& rays, const HitArrays& hits) {
  detail::check_arrays(rays, hits);
  using A = detail::BvhAccess;
  A::entries(bvh).bvh_intersect_arrays(A::data(bvh), rays, hits);
}

void occluded(const SphereBVH& bvh, std::span<const Ray> rays, std::span<bool> blocked) {
  if (rays.size() != blocked.size())
    throw std::length_error("sphray::occluded: rays and blocked differ in size");
  using A = detail::BvhAccess;
  A::entries(bvh).bvh_occluded_stream(A::data(bvh), rays.data(), blocked.data(), rays.size());
}

}  // namespace sphray
