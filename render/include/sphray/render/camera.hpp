// The camera of Ray Tracing in One Weekend: a pinhole at focal length 1, and for path mode the
// book's defocus blur. In float (Camera) or in double (Camerad, for scenes traced in double:
// the position is where float runs out, docs/double.md).
#pragma once

#include "sphray/render/scene.hpp"
#include "sphray/sphray.hpp"

namespace sphray::render {

template <Scalar S>
class BasicCamera {
 public:
  using Vec = BasicVec3<S>;
  using RayS = BasicRay<S>;

  /// Throws SceneError if spec cannot place a camera (lookfrom == lookat, vup parallel to the
  /// view direction, vfov outside (0, 180), a non-finite field) or the size is not positive.
  BasicCamera(const CameraSpec& spec, int width, int height)
      : BasicCamera(spec, vec3_cast<S>(spec.lookfrom), vec3_cast<S>(spec.lookat), width, height) {}
  /// The same with the position and target given in S (a scene's doubles), the rest from spec.
  BasicCamera(const CameraSpec& spec, Vec lookfrom, Vec lookat, int width, int height);

  /// The ray through image point (px, py): px in [0, width), py in [0, height), row 0 at the
  /// top; the centre of pixel (x, y) is (x + 0.5, y + 0.5). The direction is not normalised
  /// (as in the book): it reaches the viewport plane at distance 1 from the camera at t = 1.
  RayS ray(float px, float py) const {
    return {origin_, upper_left_ + S(px) * pixel_du_ + S(py) * pixel_dv_};
  }

  /// Path mode's ray through image point (px, py) from lens point (lx, ly) of the unit disk: it
  /// leaves lookfrom moved across the lens and passes through the point where ray(px, py) meets
  /// the plane in focus (the book's defocus blur). Without defocus it is ray(px, py).
  /// Inline: the path tracer makes one per pixel and sample, and a call returns the Ray through
  /// memory.
  RayS ray(float px, float py, float lx, float ly) const {
    return has_defocus_ ? lens_ray(px, py, lx, ly) : ray(px, py);
  }

  /// The same ray for a camera with defocus (has_defocus()), without the test: a loop over
  /// many rays then has no branch.
  RayS lens_ray(float px, float py, float lx, float ly) const {
    // The pinhole ray reaches the viewport, at distance 1 along the view direction, at t = 1:
    // the plane in focus at t = focus_dist.
    const RayS pinhole = ray(px, py);
    const Vec offset = S(lx) * lens_u_ + S(ly) * lens_v_;
    return {origin_ + offset, focus_dist_ * pinhole.dir - offset};
  }

  bool has_defocus() const { return has_defocus_; }

  int width() const { return width_; }
  int height() const { return height_; }
  Vec origin() const { return origin_; }

 private:
  Vec origin_;
  Vec upper_left_;       // from the origin to the viewport's upper-left corner
  Vec pixel_du_;         // one pixel to the right
  Vec pixel_dv_;         // one pixel down
  Vec lens_u_, lens_v_;  // the lens's radius along the image's right and up
  S focus_dist_;
  bool has_defocus_;
  int width_, height_;
};

using Camera = BasicCamera<float>;
using Camerad = BasicCamera<double>;

extern template class BasicCamera<float>;
extern template class BasicCamera<double>;

}  // namespace sphray::render
