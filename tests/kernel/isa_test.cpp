// Instruction-set naming and the SPHRAY_ISA rules (the process-wide choice itself is tested by
// running isa_probe under different environments: see CMakeLists.txt).
#include <algorithm>

#include "test_support.hpp"

namespace sphray {
namespace {

TEST(Isa, NamesRoundTrip) {
  for (Isa isa : {Isa::scalar, Isa::sse4_2, Isa::avx2, Isa::avx512, Isa::neon})
    EXPECT_EQ(parse_isa(isa_name(isa)), isa);
  EXPECT_EQ(isa_name(Isa::sse4_2), "sse4.2");
  EXPECT_FALSE(parse_isa("AVX2").has_value());
  EXPECT_FALSE(parse_isa("").has_value());
}

TEST(Isa, SupportedListIsBestFirstAndEndsWithScalar) {
  const auto isas = supported_isas();
  ASSERT_FALSE(isas.empty());
  EXPECT_EQ(isas.back(), Isa::scalar);
  for (std::size_t i = 1; i < isas.size(); ++i)
    EXPECT_GT(isa_width(isas[i - 1]), isa_width(isas[i]) - 1) << "not best first";
  for (Isa isa : isas) {
    const EntryTable* k = find_entries(isa);
    ASSERT_NE(k, nullptr);
    EXPECT_EQ(k->isa, isa);
    EXPECT_EQ(k->width, isa_width(isa));
  }
}

TEST(Isa, UnsetOrEmptyChoosesTheBest) {
  EXPECT_EQ(choose_isa(nullptr).isa, supported_isas().front());
  EXPECT_TRUE(choose_isa(nullptr).message.empty());
  EXPECT_EQ(choose_isa("").isa, supported_isas().front());
}

TEST(Isa, EachRunnableChoiceIsHonoured) {
  for (Isa isa : supported_isas()) {
    const IsaChoice c = choose_isa(std::string(isa_name(isa)).c_str());
    EXPECT_EQ(c.isa, isa);
    EXPECT_TRUE(c.message.empty());
  }
}

TEST(Isa, UnknownNameFallsBackWithAMessage) {
  const IsaChoice c = choose_isa("avx9000");
  EXPECT_EQ(c.isa, supported_isas().front());
  EXPECT_NE(c.message.find("SPHRAY_ISA=avx9000"), std::string::npos) << c.message;
  EXPECT_NE(c.message.find("using"), std::string::npos) << c.message;
}

TEST(Isa, UnrunnableChoiceFallsBackWithAMessage) {
  // Some instruction set of the list is always missing: NEON on x86, the x86 ones on ARM.
  for (Isa isa : {Isa::sse4_2, Isa::avx2, Isa::avx512, Isa::neon}) {
    if (find_entries(isa) != nullptr) continue;
    const IsaChoice c = choose_isa(std::string(isa_name(isa)).c_str());
    EXPECT_EQ(c.isa, supported_isas().front());
    EXPECT_NE(c.message.find("cannot run here"), std::string::npos) << c.message;
    return;
  }
  FAIL() << "every instruction set is runnable: none to test the fallback with";
}

TEST(Isa, ActiveIsaIsRunnable) {
  const auto isas = supported_isas();
  EXPECT_NE(std::find(isas.begin(), isas.end(), active_isa()), isas.end());
  EXPECT_EQ(active_entries().isa, active_isa());
}

}  // namespace
}  // namespace sphray

namespace sphray {
namespace {

TEST(Isa, SmallViewsGoToAKernelTheyFill) {
  const EntryTable& active = active_entries();
  for (std::size_t n = 0; n < 64; ++n) {
    const EntryTable& k = entries_for_size(n);
    ASSERT_NE(find_entries(k.isa), nullptr) << n;
    EXPECT_LE(k.width, active.width) << n;
    // Never a batch less than two thirds full when a narrower kernel exists that n fills.
    if (k.width > 4) {
      EXPECT_GE(3 * n, 2 * k.width) << n;
    }
    if (n >= 2 * active.width) {
      EXPECT_EQ(k.isa, active.isa) << n;
    }
    if (n < 2) {
      EXPECT_EQ(k.isa, Isa::scalar) << n;
    }
  }
}

TEST(Isa, DispatchedQueriesOnSmallViewsAgreeWithTheReference) {
  std::mt19937 rng(3);
  for (std::size_t n = 0; n < 40; ++n) {
    test::LooseSpheres s(n % 3);
    test::fill_random(s, n, rng);
    for (const Ray& ray : test::random_rays(2000, rng)) {
      const Hit got = intersect(s.view(), ray), want = scalar::intersect(s.view(), ray);
      ASSERT_EQ(got.id, want.id) << n;
      if (want.found()) {
        ASSERT_NEAR(got.t, want.t, 1e-4f * std::max(1.0f, std::abs(want.t))) << n;
      }
      ASSERT_EQ(occluded(s.view(), ray), scalar::occluded(s.view(), ray)) << n;
    }
  }
}

}  // namespace
}  // namespace sphray
