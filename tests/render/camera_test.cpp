// The camera against the book's construction worked by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "sphray/render/camera.hpp"

namespace sphray::render {
namespace {

void expect_near(Vec3 actual, Vec3 expected, float tolerance = 1e-5f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// Chapter 5's camera: at the origin, looking down -z, viewport 2 high and 2 * 400 / 225 wide
// at distance 1, row 0 at the top.
TEST(Camera, ChapterFiveViewport) {
  Camera camera(CameraSpec{}, 400, 225);
  float half_width = 400.0f / 225.0f;
  Ray corner = camera.ray(0, 0);
  EXPECT_EQ(corner.origin, (Vec3{0, 0, 0}));
  expect_near(corner.dir, {-half_width, 1, -1});
  expect_near(camera.ray(400, 225).dir, {half_width, -1, -1});
  expect_near(camera.ray(200, 112.5f).dir, {0, 0, -1});
  // One pixel to the right moves by the viewport width over the image width.
  expect_near(camera.ray(1, 0).dir - corner.dir, {2 * half_width / 400, 0, 0});
}

TEST(Camera, LooksFromLookfromTowardsLookat) {
  CameraSpec spec{{13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20.0f};
  Camera camera(spec, 1200, 675);
  Ray centre = camera.ray(600, 337.5f);
  EXPECT_EQ(centre.origin, (Vec3{13, 2, 3}));
  // The centre ray has length 1 (focal length 1) and points at the origin.
  Vec3 to_target = normalize(Vec3{-13, -2, -3});
  expect_near(centre.dir, to_target);
  // The top edge of the centre column is tan(10 degrees) above the axis.
  Vec3 top = camera.ray(600, 0).dir;
  float angle = std::acos(dot(normalize(top), to_target));
  EXPECT_NEAR(angle, 10.0f * 3.14159265f / 180.0f, 1e-4f);
  EXPECT_GT(top.y, centre.dir.y);
}

// The book's defocus blur on its cover camera: angle 0.6 degrees at focus distance 10, a lens of
// radius 10 tan(0.3 degrees) = 0.05236 across the image plane. Every lens point's ray passes
// through the point 10 units along the pinhole ray (the plane in focus).
TEST(Camera, DefocusRaysMeetOnThePlaneInFocus) {
  const CameraSpec spec{{13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20.0f, 0.6f, 10.0f};
  const Camera camera(spec, 1200, 675);
  ASSERT_TRUE(camera.has_defocus());
  const Vec3 w = normalize(Vec3{13, 2, 3});  // backwards along the view
  const double radius = 10.0 * std::tan(0.3 * 3.14159265358979 / 180.0);
  for (Vec3 pixel : {Vec3{600, 337.5f, 0}, Vec3{0, 0, 0}, Vec3{1199.5f, 10, 0}}) {
    const Ray pinhole = camera.ray(pixel.x, pixel.y);
    const Vec3 focus = spec.lookfrom + 10.0f * pinhole.dir;
    for (Vec3 lens : {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, -1, 0}, Vec3{-0.6f, 0.7f, 0}}) {
      const Ray r = camera.ray(pixel.x, pixel.y, lens.x, lens.y);
      const Vec3 across = r.origin - spec.lookfrom;
      EXPECT_NEAR(length(across), radius * std::hypot(lens.x, lens.y), 1e-6);
      EXPECT_NEAR(dot(across, w), 0.0f, 1e-6f);  // the lens lies across the view
      expect_near(r.origin + r.dir, focus, 1e-4f);
    }
  }
  // No blur: the pinhole ray, whatever the lens point.
  const Camera pinhole({{13, 2, 3}, {0, 0, 0}, {0, 1, 0}, 20.0f}, 1200, 675);
  EXPECT_FALSE(pinhole.has_defocus());
  EXPECT_EQ(pinhole.ray(3, 4, 0.5f, 0.5f).origin, (Vec3{13, 2, 3}));
  EXPECT_EQ(pinhole.ray(3, 4, 0.5f, 0.5f).dir, pinhole.ray(3, 4).dir);
}

TEST(Camera, RefusesWhatCannotBePlaced) {
  EXPECT_THROW(Camera(CameraSpec{{1, 1, 1}, {1, 1, 1}, {0, 1, 0}, 40}, 10, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 5, 0}, {0, 0, 0}, {0, 1, 0}, 40}, 10, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 0}, 10, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 180}, 10, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, NAN}, {0, 0, -1}, {0, 1, 0}, 90}, 10, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{}, 0, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, -1, 10}, 10, 10),
               SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 180, 10}, 10, 10),
               SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 1, 0}, 10, 10), SceneError);
  EXPECT_THROW(Camera(CameraSpec{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 1, NAN}, 10, 10),
               SceneError);
}

}  // namespace
}  // namespace sphray::render
