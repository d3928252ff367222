// Particle files as scenes: the readers of sphray::particles, the colours they give (none stored
// without: an empty Scene::colors is grey everywhere, and 100M spheres would spend 1.2 GB on one
// grey), the material asked for, and the camera framed on the particles' box as random:N's is.
#include <algorithm>
#include <cmath>

#include "sphray/particles/particles.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {

namespace {

// The text reader checks these; a .sphp file's floats arrive as written.
void check_particle(const std::filesystem::path& file, std::size_t i, Vec3 c, float r) {
  if (!isfinite(c) || !(r > 0.0f && r <= 1e17f) || std::abs(c.x) > 1e17f || std::abs(c.y) > 1e17f ||
      std::abs(c.z) > 1e17f) {
    throw SceneError(file.string() + ": particle " + std::to_string(i) + " (byte offset " +
                     std::to_string(particles::kSphpHeaderBytes + particles::kSphpRecordBytes * i) +
                     "): expected a centre of at most 1e17 in magnitude and a radius in (0, "
                     "1e17], got (" +
                     std::to_string(c.x) + ", " + std::to_string(c.y) + ", " + std::to_string(c.z) +
                     ") r " + std::to_string(r));
  }
}

}  // namespace

ParticleSpheres load_particle_spheres(const std::filesystem::path& file,
                                      const SceneOptions& options) {
  particles::Points points;
  try {
    points = particles::read_particle_file(file, {options.radius});
  } catch (const particles::ParticleError& e) {
    throw SceneError(e.what());
  }
  if (points.spheres.size() == 0)  // only a .sphp file may be empty; the text reader refuses
    throw SceneError(file.string() + ": expected particles, the file has none");
  const SphereView v = points.spheres.view();
  for (std::size_t i = 0; i < v.count; ++i)
    check_particle(file, i, {v.cx[i], v.cy[i], v.cz[i]}, v.radius[i]);
  return {std::move(points.spheres), std::move(points.colors)};
}

Scene load_particle_scene(const std::filesystem::path& file, const SceneOptions& options) {
  ParticleSpheres points = load_particle_spheres(file, options);
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
  return scene;
}

}  // namespace sphray::render
