// The queries allocate nothing: the stream calls keep their working memory (a chunk's walks,
// the shadow rays' sort window) on the call stack. docs/kernel.md promises a bound for
// embedders whose threads have small stacks (fibers, musl's 128 KiB default). Each call runs on
// a thread whose stack is a buffer painted with a byte pattern; the bytes it overwrote are the
// stack it used (thread start-up and thread-local storage included, so the figure is an upper
// bound). Sanitizers and unoptimised builds enlarge every frame: there only the answers are
// checked.
#include <gtest/gtest.h>
#include <pthread.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "test_support.hpp"

namespace sphray {
namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || !defined(NDEBUG)
constexpr bool kFramesAsBuilt = false;
#else
constexpr bool kFramesAsBuilt = true;
#endif

// docs/kernel.md, "Guarantees": the stack a query may take on any instruction set.
constexpr std::size_t kPromisedStack = 96 * 1024;
constexpr std::size_t kPaintedStack = 1024 * 1024;  // room for sanitized frames
constexpr unsigned char kPaint = 0xA5;

// Runs work on a thread with a painted stack; returns how many of its bytes were written.
std::size_t stack_used_by(const std::function<void()>& work) {
  std::vector<unsigned char> stack(kPaintedStack, kPaint);
  pthread_attr_t attributes;
  EXPECT_EQ(pthread_attr_init(&attributes), 0);
  EXPECT_EQ(pthread_attr_setstack(&attributes, stack.data(), stack.size()), 0);
  pthread_t thread;
  auto* job = const_cast<std::function<void()>*>(&work);
  const auto run = [](void* p) -> void* {
    (*static_cast<std::function<void()>*>(p))();
    return nullptr;
  };
  EXPECT_EQ(pthread_create(&thread, &attributes, run, job), 0);
  EXPECT_EQ(pthread_join(thread, nullptr), 0);
  pthread_attr_destroy(&attributes);
  // The stack grows down from the buffer's end: the untouched bytes are at its start.
  std::size_t untouched = 0;
  while (untouched < stack.size() && stack[untouched] == kPaint)
    ++untouched;
  return stack.size() - untouched;
}

// Camera rays of a 256 x 256 pinhole image, and shadow rays towards a sun from where they hit:
// the stream's packets, its line packets and its rays alone all run.
struct Workload {
  SphereSoA spheres;
  std::vector<Ray> camera;
  std::vector<Ray> shadows;
};

Workload make_workload(std::size_t n) {
  std::mt19937 rng(17);
  Workload w;
  test::fill_random(w.spheres, n, rng);
  const SphereBVH tree(w.spheres.view());
  const Vec3 sun = normalize(Vec3{0.6f, 1.0f, 0.45f});
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      const Vec3 d{(static_cast<float>(x) - 128.0f) / 128.0f,
                   (static_cast<float>(y) - 128.0f) / 128.0f, 1.0f};
      const Ray ray{{0.0f, 0.0f, -30.0f}, normalize(d)};
      w.camera.push_back(ray);
      const Hit hit = intersect(tree, ray);
      if (hit.found()) w.shadows.push_back(spawn(surface(w.spheres.view(), ray, hit), sun));
    }
  }
  return w;
}

class Stack : public testing::TestWithParam<std::size_t> {};

TEST_P(Stack, StreamCallsStayWithinThePromisedStack) {
  const Workload w = make_workload(GetParam());
  const SphereBVH tree(w.spheres.view());
  ASSERT_GT(w.shadows.size(), 1000u);

  std::vector<Hit> hits(w.camera.size());
  std::unique_ptr<bool[]> blocked(new bool[w.shadows.size()]);
  const std::span<bool> blocked_span(blocked.get(), w.shadows.size());
  const std::size_t closest = stack_used_by([&] { intersect(tree, w.camera, hits); });
  const std::size_t shadow = stack_used_by([&] { occluded(tree, w.shadows, blocked_span); });
  const std::size_t brute = stack_used_by([&] { intersect(w.spheres.view(), w.camera, hits); });

  for (std::size_t i = 0; i < w.shadows.size(); ++i)
    ASSERT_EQ(blocked[i], occluded(tree, w.shadows[i])) << "shadow ray " << i;
  std::vector<Hit> tree_hits(w.camera.size());
  intersect(tree, w.camera, tree_hits);
  for (std::size_t i = 0; i < w.camera.size(); ++i) {
    ASSERT_EQ(hits[i].id, tree_hits[i].id) << "camera ray " << i;
    ASSERT_EQ(hits[i].t, tree_hits[i].t) << "camera ray " << i;
  }

  RecordProperty("closest_stream_bytes", static_cast<int>(closest));
  RecordProperty("occluded_stream_bytes", static_cast<int>(shadow));
  if (!kFramesAsBuilt) return;
  EXPECT_LE(closest, kPromisedStack);
  EXPECT_LE(shadow, kPromisedStack);
  EXPECT_LE(brute, kPromisedStack);
  // The measurement itself: a call that uses the stack must show.
  EXPECT_GT(shadow, 4096u);
}

INSTANTIATE_TEST_SUITE_P(Trees, Stack, testing::Values(486, 4096, 65536));

}  // namespace
}  // namespace sphray
