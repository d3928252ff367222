// SphereBVH and SphereBVHd: own the built arrays and forwards queries to the kernel it was laid out
// for.
#include "sphray/bvh.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>

#include "bvh/build.hpp"
#include "bvh/bvh_data.hpp"
#include "dispatch/entry_table.hpp"
#include "storage/ray_columns.hpp"

namespace sphray {

BuildCancelled::BuildCancelled() : std::runtime_error("sphray::SphereBVH: build cancelled") {}

template <Scalar S>
struct BasicSphereBVH<S>::Storage {
  detail::BasicBvhArrays<S> arrays;
  detail::BasicBvhData<S> data;  // views of arrays

  static std::size_t width(const detail::EntryTable& entries) {
    return std::is_same_v<S, float> ? entries.bvh_width : entries.bvh_width_d;
  }

  static std::unique_ptr<Storage> build(View spheres, const detail::EntryTable& entries,
                                        const BvhBuildOptions& options,
                                        const BuildProgress& progress = {}) {
    auto storage = std::make_unique<Storage>();
    storage->arrays = detail::build_bvh(spheres, width(entries), options, progress);
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

template <Scalar S>
BasicSphereBVH<S>::BasicSphereBVH()
    : BasicSphereBVH(View{nullptr, nullptr, nullptr, nullptr, 0, 0}) {}

template <Scalar S>
BasicSphereBVH<S>::BasicSphereBVH(View spheres, BvhBuildOptions options)
    : BasicSphereBVH(spheres, bvh_isa(spheres.count), options) {}

template <Scalar S>
BasicSphereBVH<S>::BasicSphereBVH(View spheres, Isa isa, BvhBuildOptions options)
    : entries_(&entries_for(isa)) {
  storage_ = Storage::build(spheres, *entries_, options);
}

template <Scalar S>
BasicSphereBVH<S>::BasicSphereBVH(View spheres, BvhBuildOptions options,
                                  const BuildProgress& progress)
    : entries_(&entries_for(bvh_isa(spheres.count))) {
  storage_ = Storage::build(spheres, *entries_, options, progress);
}

// A moved-from tree keeps its kernel and loses its storage: it reads as the empty tree.
template <Scalar S>
BasicSphereBVH<S>::BasicSphereBVH(BasicSphereBVH&& other) noexcept = default;
template <Scalar S>
BasicSphereBVH<S>& BasicSphereBVH<S>::operator=(BasicSphereBVH&& other) noexcept = default;
template <Scalar S>
BasicSphereBVH<S>::~BasicSphereBVH() = default;

template <Scalar S>
void BasicSphereBVH<S>::refit(View spheres) {
  if (!storage_)
    storage_ = Storage::build({nullptr, nullptr, nullptr, nullptr, 0, 0}, *entries_, {});
  detail::refit_bvh(storage_->arrays, spheres);
  storage_->data = storage_->arrays.data();  // the leaf overlap changed
}

template <Scalar S>
std::size_t BasicSphereBVH<S>::size() const {
  return detail::BvhAccess::data(*this).count;
}

template <Scalar S>
Isa BasicSphereBVH<S>::isa() const {
  return entries_->isa;
}

template <Scalar S>
std::size_t BasicSphereBVH<S>::memory_bytes() const {
  return detail::BvhAccess::data(*this).memory_bytes;
}

template class BasicSphereBVH<float>;
template class BasicSphereBVH<double>;

// The empty tree's arrays: no nodes, no spheres. Every query misses it (count 0 takes the
// scalar walk, which visits nothing).
constexpr detail::BvhData kEmptyTree{};
constexpr detail::BvhDatad kEmptyTreed{};

const detail::BvhData& detail::BvhAccess::data(const SphereBVH& bvh) {
  return bvh.storage_ ? bvh.storage_->data : kEmptyTree;
}

const detail::BvhDatad& detail::BvhAccess::data(const SphereBVHd& bvh) {
  return bvh.storage_ ? bvh.storage_->data : kEmptyTreed;
}

namespace {

using detail::in_precision;
using Access = detail::BvhAccess;

// The queries, written once for both precisions: the entry of the tree's kernel in its own.
template <Scalar S>
BasicHit<S> tree_intersect(const BasicSphereBVH<S>& bvh, const BasicRay<S>& ray) {
  const EntryTable& e = Access::entries(bvh);
  return in_precision<S>(e.bvh_intersect, e.bvh_intersect_d)(Access::data(bvh), ray);
}

template <Scalar S>
bool tree_occluded(const BasicSphereBVH<S>& bvh, const BasicRay<S>& ray) {
  const EntryTable& e = Access::entries(bvh);
  return in_precision<S>(e.bvh_occluded, e.bvh_occluded_d)(Access::data(bvh), ray);
}

template <Scalar S>
void tree_intersect(const BasicSphereBVH<S>& bvh, std::span<const BasicRay<S>> rays,
                    std::span<BasicHit<S>> hits) {
  if (rays.size() != hits.size())
    throw std::length_error("sphray::intersect: rays and hits differ in size");
  const EntryTable& e = Access::entries(bvh);
  in_precision<S>(e.bvh_intersect_stream, e.bvh_intersect_stream_d)(Access::data(bvh), rays.data(),
                                                                    hits.data(), rays.size());
}

template <Scalar S>
void tree_occluded(const BasicSphereBVH<S>& bvh, std::span<const BasicRay<S>> rays,
                   std::span<bool> blocked) {
  if (rays.size() != blocked.size())
    throw std::length_error("sphray::occluded: rays and blocked differ in size");
  const EntryTable& e = Access::entries(bvh);
  in_precision<S>(e.bvh_occluded_stream, e.bvh_occluded_stream_d)(Access::data(bvh), rays.data(),
                                                                  blocked.data(), rays.size());
}

}  // namespace

Hit intersect(const SphereBVH& bvh, const Ray& ray) {
  return tree_intersect(bvh, ray);
}

bool occluded(const SphereBVH& bvh, const Ray& ray) {
  return tree_occluded(bvh, ray);
}

void intersect(const SphereBVH& bvh, std::span<const Ray> rays, std::span<Hit> hits) {
  tree_intersect(bvh, rays, hits);
}

void intersect(const SphereBVH& bvh, const RayArrays& rays, const HitArrays& hits) {
  detail::check_arrays(rays, hits);
  Access::entries(bvh).bvh_intersect_arrays(Access::data(bvh), rays, hits);
}

void occluded(const SphereBVH& bvh, std::span<const Ray> rays, std::span<bool> blocked) {
  tree_occluded(bvh, rays, blocked);
}

Hitd intersect(const SphereBVHd& bvh, const Rayd& ray) {
  return tree_intersect(bvh, ray);
}

bool occluded(const SphereBVHd& bvh, const Rayd& ray) {
  return tree_occluded(bvh, ray);
}

void intersect(const SphereBVHd& bvh, std::span<const Rayd> rays, std::span<Hitd> hits) {
  tree_intersect(bvh, rays, hits);
}

void intersect(const SphereBVHd& bvh, const RayArraysd& rays, const HitArraysd& hits) {
  detail::check_arrays(rays, hits);
  detail::intersect_in_chunks(rays, hits, [&](std::span<const Rayd> in, std::span<Hitd> out) {
    tree_intersect(bvh, in, out);
  });
}

void occluded(const SphereBVHd& bvh, std::span<const Rayd> rays, std::span<bool> blocked) {
  tree_occluded(bvh, rays, blocked);
}

}  // namespace sphray
