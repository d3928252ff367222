// Tracing a batch of rays from numpy: the rays assembled chunk by chunk from the caller's
// arrays (never all at once), the chunks spread over oneTBB's workers when the batch is large
// enough to pay for it. Runs without the GIL: it touches no Python object, but between chunks
// the calling thread lets Python answer a Ctrl-C (interruption.hpp).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>

#include "arrays.hpp"
#include "interruption.hpp"
#include "sphray/sphray.hpp"

namespace sphray::python {

/// Rays per chunk: small enough that a chunk's rays and hits stay in L1/L2, large enough that
/// the per-chunk overhead is noise.
inline constexpr std::size_t kChunkRays = 1024;
/// Below this many rays a batch runs on the calling thread: waking the workers would cost more
/// than the trace.
inline constexpr std::size_t kParallelFromRays = 4 * kChunkRays;

/// Calls piece(k) for k in [0, pieces), on oneTBB's workers when `parallel`, else on the calling
/// thread. piece must be safe to call from several threads at once for different k. Throws
/// Interrupted when a signal handler raised meanwhile (to be called without the GIL).
template <typename Piece>
void for_each_piece(std::size_t pieces, bool parallel, const Piece& piece) {
  Interruption interruption;
  const auto run = [&](std::size_t k) {
    piece(k);
    interruption.check();
  };
  if (!parallel) {
    for (std::size_t k = 0; k < pieces; ++k)
      run(k);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, pieces),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k)
                        run(k);
                    });
}

/// Calls chunk(begin, end) over [0, count) in pieces of kChunkRays (the last may be shorter),
/// piece k covering [k kChunkRays, (k + 1) kChunkRays), in parallel for large counts, as
/// for_each_piece.
template <typename Chunk>
void for_each_chunk(std::size_t count, const Chunk& chunk) {
  for_each_piece(
      (count + kChunkRays - 1) / kChunkRays, count >= kParallelFromRays,
      [&](std::size_t k) { chunk(k * kChunkRays, std::min(count, (k + 1) * kChunkRays)); });
}

/// The directions of a batch, checked against its origins' shape.
template <Scalar S>
Vec3Rows<S> directions_like(const Vec3Rows<S>& origins, const py::handle& directions,
                            const std::string& name = "directions") {
  Vec3Rows<S> d(name.c_str(), directions);
  if (d.leading_shape() != origins.leading_shape()) {
    throw py::value_error(name + ": expected the shape of origins " + origins.shape() + ", got " +
                          d.shape());
  }
  return d;
}

/// The rays of a batch as the caller gave them: origins and directions (..., 3), and tmin,
/// tmax and mask as scalars or one per ray; rays of the scene's scalar S.
template <Scalar S>
struct RayBatch {
  const Vec3Rows<S>& origins;
  const Vec3Rows<S>& directions;
  const ScalarPerRow<S>& tmin;
  const ScalarPerRow<S>& tmax;
  const MaskPerRow& mask;

  std::size_t size() const { return origins.size(); }
  BasicRay<S> operator[](std::size_t i) const {
    return {origins[i], directions[i], tmin[i], tmax[i], mask[i]};
  }
};

/// A ray query's arguments, parsed and checked once: origins, directions (of the origins'
/// shape), and tmin, tmax and mask (scalars or one per ray).
template <Scalar S>
struct RayArguments {
  RayArguments(const py::handle& o, const py::handle& d, const py::handle& tmin,
               const py::handle& tmax, const py::handle& mask)
      : origins("origins", o),
        directions(directions_like(origins, d)),
        tmin("tmin", tmin, origins.leading_shape()),
        tmax("tmax", tmax, origins.leading_shape()),
        mask(mask, origins.leading_shape()) {}

  RayBatch<S> batch() const { return {origins, directions, tmin, tmax, mask}; }

  Vec3Rows<S> origins, directions;
  ScalarPerRow<S> tmin, tmax;
  MaskPerRow mask;
};

}  // namespace sphray::python
