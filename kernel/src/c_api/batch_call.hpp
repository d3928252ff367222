// The frame every batch query shares: its sphray_query_args read, its arguments checked, then
// its work over [0, count) on the threads the args ask for, with every exception mapped to a
// status (last_error.hpp). Each call adds only its own checks and its per-range work.
#pragma once

#include <cstddef>
#include <cstdint>

#include "c_api/checks.hpp"
#include "c_api/last_error.hpp"
#include "c_api/parallel_chunks.hpp"

namespace sphray::c_api {

/// A query's options (sphray_query_args) with their defaults filled in.
struct QueryOptions {
  const std::uint32_t* masks = nullptr;  // null: every ray has every bit
  unsigned threads = 1;
};

/// What the inputs of a query are: masks apply to rays only.
enum class Inputs { rays, points };

/// What args say (NULL: the defaults). Fails on a struct_size this library does not know (a
/// newer caller's options would be silently dropped otherwise), or on masks for points.
inline int read_args(const sphray_query_args* args, Inputs inputs, const char* function,
                     QueryOptions& options) noexcept {
  if (args == nullptr) return SPHRAY_OK;
  if (args->struct_size != sizeof(sphray_query_args))
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function,
                "args->struct_size is not sizeof(sphray_query_args)");
  if (args->masks != nullptr && inputs != Inputs::rays)
    return fail(SPHRAY_ERROR_INVALID_ARGUMENT, function, "masks apply to rays, not to points");
  options.masks = args->masks;
  options.threads = args->threads;
  return SPHRAY_OK;
}

/// The checks a batch query of precision S starts with: args into options; then, for a count of
/// 0, a live scene of precision S alone (empty work: the arrays may be NULL), otherwise the
/// scene, the input and output arrays and the count. The caller returns on a failure and on a
/// count of 0.
template <Scalar S = float>
int check_batch(const sphray_scene* scene, const void* in, const void* out, std::size_t count,
                const sphray_query_args* args, Inputs inputs, const char* function,
                QueryOptions& options) noexcept {
  if (int status = read_args(args, inputs, function, options); status != SPHRAY_OK) return status;
  if (count == 0) return check_scene_in<S>(scene, function);
  return check_query<S>(scene, in, out, count, function,
                        inputs == Inputs::rays ? "rays is NULL" : "points is NULL");
}

/// range(worker, begin, end) over [0, count) on the threads options ask for; SPHRAY_OK, or the
/// status of what it threw on any of them.
template <class Range>
int run_batch(const char* function, std::size_t count, const QueryOptions& options,
              Range&& range) noexcept {
  return guarded(function, [&] {
    parallel_chunks(count, parallel_threads(count, options.threads), range);
    return SPHRAY_OK;
  });
}

}  // namespace sphray::c_api
