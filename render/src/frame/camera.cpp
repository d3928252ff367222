#include "sphray/render/camera.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace sphray::render {
namespace {

template <Scalar S>
void check_camera(const CameraSpec& spec, BasicVec3<S> lookfrom, BasicVec3<S> lookat, int width,
                  int height) {
  if (width <= 0 || height <= 0) {
    throw SceneError("camera: expected a positive image size, got " + std::to_string(width) + "x" +
                     std::to_string(height));
  }
  if (!isfinite(lookfrom) || !isfinite(lookat) || !isfinite(spec.vup) ||
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
  const BasicVec3<S> back = lookfrom - lookat;
  if (length_squared(back) == S(0)) {
    throw SceneError("camera: expected lookfrom and lookat to differ");
  }
  if (length_squared(cross(vec3_cast<S>(spec.vup), back)) == S(0)) {
    throw SceneError("camera: expected vup not parallel to the view direction");
  }
}

}  // namespace

template <Scalar S>
BasicCamera<S>::BasicCamera(const CameraSpec& spec, Vec lookfrom, Vec lookat, int width, int height)
    : width_(width), height_(height) {
  check_camera(spec, lookfrom, lookat, width, height);
  // The book's construction: an orthonormal frame (u right, v up, w back), a viewport at
  // distance 1 whose height follows from vfov and whose width keeps the pixels square.
  S theta = S(spec.vfov) * std::numbers::pi_v<S> / S(180);
  S viewport_height = S(2) * std::tan(theta / S(2));
  S viewport_width = viewport_height * static_cast<S>(width) / static_cast<S>(height);
  Vec w = normalize(lookfrom - lookat);
  Vec u = normalize(cross(vec3_cast<S>(spec.vup), w));
  Vec v = cross(w, u);
  Vec viewport_u = viewport_width * u;
  Vec viewport_v = viewport_height * -v;  // rows run downwards
  origin_ = lookfrom;
  pixel_du_ = viewport_u / static_cast<S>(width);
  pixel_dv_ = viewport_v / static_cast<S>(height);
  upper_left_ = -w - viewport_u / S(2) - viewport_v / S(2);
  // The book's defocus disk: radius focus_dist tan(angle / 2), in the plane of u and v.
  const S lens_radius =
      S(spec.focus_dist) * std::tan(S(spec.defocus_angle) * std::numbers::pi_v<S> / S(360));
  lens_u_ = lens_radius * u;
  lens_v_ = lens_radius * v;
  focus_dist_ = S(spec.focus_dist);
  has_defocus_ = lens_radius > S(0);
}

template class BasicCamera<float>;
template class BasicCamera<double>;

}  // namespace sphray::render
