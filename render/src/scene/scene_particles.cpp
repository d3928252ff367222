// Particle files as scenes: the readers of sphray::particles (which check every particle), the
// colours they give (none stored without: an empty Scene::colors is grey everywhere, and 100M
// spheres would spend 1.2 GB on one grey), the material asked for, and the camera framed on the
// particles' box as random:N's is.
#include <algorithm>
#include <cmath>

#include "sphray/particles/particles.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

Scene load_particle_scene(const std::filesystem::path& file, const SceneOptions& options) {
  particles::Points points;
  try {
    points = particles::read_particle_file(
        file, {options.radius, options.precision == Precision::float64});
  } catch (const particles::ParticleError& e) {
    throw SceneError(e.what());
  }
  if (points.spheres.size() == 0)  // only a .sphp file may be empty; the text readers refuse
    throw SceneError(file.string() + ": expected particles, the file has none");
  Scene scene;
  scene.name = file.filename().string();
  const SphereView v = points.spheres.view();
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < v.count; ++i) {
    const Vec3 c{v.cx[i], v.cy[i], v.cz[i]};
    const float r = v.radius[i];
    lo = {std::min(lo.x, c.x - r), std::min(lo.y, c.y - r), std::min(lo.z, c.z - r)};
    hi = {std::max(hi.x, c.x + r), std::max(hi.y, c.y + r), std::max(hi.z, c.z + r)};
  }
  scene.spheres = std::move(points.spheres);
  scene.colors = std::move(points.colors);  // empty without colours: grey (color_of)
  if (options.material) scene.default_material = *options.material;
  // Half the box's diagonal bounds every sphere; computed in double, the corners of a box up to
  // 1e17 across stay finite.
  const double dx = double{hi.x} - lo.x, dy = double{hi.y} - lo.y, dz = double{hi.z} - lo.z;
  const auto bound = static_cast<float>(0.5 * std::sqrt(dx * dx + dy * dy + dz * dz));
  scene.camera = framing((lo + hi) * 0.5f, bound);
  if (options.precision == Precision::float64) {
    // .sphp and PDB have no more digits than their floats and give no doubles: widened here.
    scene.doubles = points.doubles.empty() ? doubles_of(scene)
                                           : SceneDoubles{std::move(points.doubles),
                                                          vec3_cast<double>(scene.camera.lookfrom),
                                                          vec3_cast<double>(scene.camera.lookat)};
  }
  return scene;
}

}  // namespace sphray::render
