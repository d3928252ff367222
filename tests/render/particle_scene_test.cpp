// Particle files as scenes, through the library: a file without colours stores none (an empty
// Scene::colors is grey everywhere), and renders byte for byte as the same spheres with an
// explicit grey for each, as every sphere was given before, in every mode.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

#include "sphray/render/renderer.hpp"
#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

std::filesystem::path scratch_file(const std::string& name, const std::string& text) {
  const auto file = std::filesystem::temp_directory_path() /
                    ("sphray-particle-scene-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

TEST(ParticleScene, AFileWithoutColoursStoresNoneAndRendersAsExplicitGrey) {
  // Spheres that touch and shadow one another, so that shaded and path modes bounce between them.
  const auto file = scratch_file("plain.xyz", "0 0 0 1\n1.5 0.3 0.2 0.6\n-1 1.2 0.5 0.5\n");
  for (const char* material : {"lambertian", "metal"}) {
    SceneOptions options;
    if (std::string(material) == "metal") options.material = Material{MaterialKind::metal};
    const Scene plain = load_particle_scene(file, options);
    EXPECT_TRUE(plain.colors.empty());
    EXPECT_TRUE(plain.materials.empty());
    Scene grey = load_particle_scene(file, options);
    grey.colors.assign(grey.spheres.size(), Vec3{0.5f, 0.5f, 0.5f});
    for (Mode mode : {Mode::normals, Mode::flat, Mode::depth, Mode::id, Mode::shaded, Mode::path}) {
      RenderOptions o;
      o.mode = mode;
      o.width = 48;
      o.height = 27;
      o.spp = 4;
      EXPECT_EQ(render(plain, o).rgb, render(grey, o).rgb)
          << material << " in " << mode_name(mode) << " mode";
    }
  }
  std::filesystem::remove(file);
}

TEST(ParticleScene, TheFilesColoursAreKeptOnePerSphere) {
  const auto file = scratch_file("coloured.xyz", "0 0 0 1 0.1 0.2 0.3\n2 0 0 1 0.4 0.5 0.6\n");
  const Scene scene = load_particle_scene(file);
  ASSERT_EQ(scene.colors.size(), 2u);
  EXPECT_EQ(color_of(scene, 1).y, 0.5f);
  EXPECT_EQ(material_of(scene, 0).albedo.z, 0.3f);
  EXPECT_EQ(material_of(scene, 0).kind, MaterialKind::lambertian);
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace sphray::render
