// The build's progress, for a BuildProgress (sphray/bvh.hpp): how many spheres are placed, counted
// once per subtree small enough to be built in one go, and the caller's function asked at every
// larger node whether to go on. Safe to use from the builder's threads at once.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>

#include "sphray/bvh.hpp"

namespace sphray::detail {

class ProgressCount {
 public:
  /// Subtrees of fewer spheres are counted when done, and not asked about: they take a few
  /// microseconds, and a call per node would cost more than the build of a small one.
  static constexpr std::size_t kAskFrom = 1024;

  ProgressCount(const BuildProgress& report, std::size_t spheres)
      : report_(report), spheres_(spheres) {}

  /// spheres more are in finished subtrees.
  void placed(std::size_t spheres) {
    if (report_) placed_.fetch_add(spheres, std::memory_order_relaxed);
  }

  /// Asks the caller's function, if any; throws BuildCancelled when it says stop.
  void ask() const {
    if (!report_) return;
    const double done = spheres_ == 0
                            ? 1.0
                            : static_cast<double>(placed_.load(std::memory_order_relaxed)) /
                                  static_cast<double>(spheres_);
    if (!report_(done)) throw BuildCancelled();
  }

  /// Tells the caller's function the build is complete (it may still cancel it).
  void done() const {
    if (report_ && !report_(1.0)) throw BuildCancelled();
  }

 private:
  const BuildProgress& report_;
  std::size_t spheres_;
  std::atomic<std::size_t> placed_{0};
};

}  // namespace sphray::detail
