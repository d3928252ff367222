#include <gtest/gtest.h>

#include <sphray/sphray.hpp>

TEST(Smoke, Rtiow) {
  sphray::SphereSoA s;
  s.add({0, 0, -1}, 0.5f);
  for (auto isa : sphray::supported_isas()) {
    const auto* k = sphray::find_kernel(isa);
    sphray::Ray r{{0, 0, 0}, {0, 0, -1}};
    auto h = k->intersect(s.view(), r);
    EXPECT_EQ(h.id, 0u) << sphray::isa_name(isa);
    EXPECT_FLOAT_EQ(h.t, 0.5f);
  }
}
