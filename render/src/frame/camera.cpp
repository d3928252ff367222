#include "sphray/render/camera.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace sphray::render {
namespace {

void check_camera(const CameraSpec& spec, int width, int height) {
  if (width <= 0 || height <= 0) {
    throw SceneError("camera: expected a positive image size, got " + std::to_string(width) + "x" +
                     std::to_string(height));
  }
  if (!isfinite(spec.lookfrom) || !isfinite(spec.lookat) || !isfinite(spec.vup) ||
      !std::isfinite(spec.vfov)) {
    throw SceneError("camera: expected finite lookfrom, lookat, vup and vfov");
  }
  if (!std::isfinite(spec.defocus_angle) ||
      !(spec.defocus_angle >= 0.0f && spec.defocus_angle < 180.0f)) {
    throw SceneError("camera: expected defocus_angle in [0, 180) degrees, got " +
                     std::to_string(spec.defocus_angle));
  }
  if (!std::isfinite(spec.focus_dist) || !(spec.focus_dist > 0.0f)) {
    throw SceneError("camera: expected a positive focus_dist, got " +
                     std::to_string(spec.focus_dist));
  }
  if (!(spec.vfov > 0.0f && spec.vfov < 180.0f)) {
    throw SceneError("camera: expected vfov in (0, 180) degrees, got " + std::to_string(spec.vfov));
  }
  Vec3 back = spec.lookfrom - spec.lookat;
  if (length_squared(back) == 0.0f) {
    throw SceneError("camera: expected lookfrom and lookat to differ");
  }
  if (length_squared(cross(spec.vup, back)) == 0.0f) {
    throw SceneError("camera: expected vup not parallel to the view direction");
  }
}

}  // namespace

Camera::Camera(const CameraSpec& spec, int width, int height) : width_(width), height_(height) {
  check_camera(spec, width, height);
  // The book's construction: an orthonormal frame (u right, v up, w back), a viewport at
  // distance 1 whose height follows from vfov and whose width keeps the pixels square.
  float theta = spec.vfov * std::numbers::pi_v<float> / 180.0f;
  float viewport_height = 2.0f * std::tan(theta / 2.0f);
  float viewport_width = viewport_height * static_cast<float>(width) / static_cast<float>(height);
  Vec3 w = normalize(spec.lookfrom - spec.lookat);
  Vec3 u = normalize(cross(spec.vup, w));
  Vec3 v = cross(w, u);
  Vec3 viewport_u = viewport_width * u;
  Vec3 viewport_v = viewport_height * -v;  // rows run downwards
  origin_ = spec.lookfrom;
  pixel_du_ = viewport_u / static_cast<float>(width);
  pixel_dv_ = viewport_v / static_cast<float>(height);
  upper_left_ = -w - viewport_u / 2.0f - viewport_v / 2.0f;
  // The book's defocus disk: radius focus_dist tan(angle / 2), in the plane of u and v.
  const float lens_radius =
      spec.focus_dist * std::tan(spec.defocus_angle * std::numbers::pi_v<float> / 360.0f);
  lens_u_ = lens_radius * u;
  lens_v_ = lens_radius * v;
  focus_dist_ = spec.focus_dist;
  has_defocus_ = lens_radius > 0.0f;
}

}  // namespace sphray::render
