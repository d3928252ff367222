// sphray_book_path (bench/book_path_tracer.cpp), issue 33's baseline, against `sphray render -m
// path`: both render the same scene at 32x18 with many samples a pixel, and must agree in
// expectation. Their random numbers differ, so the images differ in noise: the mean absolute
// difference of their bytes is small but not 0 (about what two seeds of sphray give). Means of
// the signed differences average the noise out and keep a bias: over the whole image (a bias
// everywhere: the sky, the depth rule) and over blocks of 4x4 pixels (a bias on one sphere: a
// material, the camera's sample positions). A baseline made wrong on purpose must differ by more
// than the bounds, or the comparison could not fail: its paths cut after the camera ray
// (--max-depth 1) on both scenes, and after three rays on the scene with glass and mirrors,
// whose light needs more. The rays a path traces are counted alike by both (camera and bounce
// rays, every ray intersected with the scene), so that bench/path_vs_book.py compares like with
// like: their means per path agree too.
#define STB_IMAGE_IMPLEMENTATION
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "command_run.hpp"
#include "test_pixels.hpp"

namespace sphray::test {
namespace {

// 32x18 at 2048 samples: the file runs in about two seconds in a release build.
constexpr int kWidth = 32, kHeight = 18;
constexpr const char* kFrame = "-W 32 -H 18 --spp 2048";
constexpr double kCameraRays = 32.0 * 18 * 2048;

// Bounds for two renders that agree in expectation, in levels of 255 per byte, each at least
// twice the largest measured between the two programs over several seeds of the book's (and
// between two seeds of sphray) on materials.json, the noisier scene: the mean absolute
// difference, the mean signed difference and the largest mean signed difference of a block. The
// wrong baselines exceed twice the first two. A dielectric without Schlick's reflection (always
// refracting short of the critical angle) exceeds the third by more than twice.
constexpr double kMaxMeanAbsolute = 1.0;
constexpr double kMaxMeanSigned = 0.2;
constexpr double kMaxBlockSigned = 2.0;
constexpr int kBlock = 4;

struct Difference {
  double mean_absolute = 0;  // |a - b| over every byte
  double mean_signed = 0;    // a - b over every byte
  double block_signed = 0;   // the largest |a - b| of a channel's mean over a block of pixels
};

// a and b are kWidth x kHeight.
Difference difference(const Pixels& a, const Pixels& b) {
  Difference d;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const int delta = a.rgb[i] - b.rgb[i];
    d.mean_absolute += std::abs(delta);
    d.mean_signed += delta;
  }
  d.mean_absolute /= static_cast<double>(a.rgb.size());
  d.mean_signed /= static_cast<double>(a.rgb.size());
  for (int y0 = 0; y0 < kHeight; y0 += kBlock) {
    for (int x0 = 0; x0 < kWidth; x0 += kBlock) {
      for (int c = 0; c < 3; ++c) {
        int sum = 0, count = 0;
        for (int y = y0; y < std::min(y0 + kBlock, kHeight); ++y) {
          for (int x = x0; x < std::min(x0 + kBlock, kWidth); ++x, ++count)
            sum += a.at(x, y)[c] - b.at(x, y)[c];
        }
        d.block_signed = std::max(d.block_signed, std::fabs(static_cast<double>(sum) / count));
      }
    }
  }
  return d;
}

struct Rays {
  double camera = 0, bounce = 0;
};

// The ray counts of a summary line ("(N camera + M bounce + 0 shadow rays").
Rays rays_of(const std::string& summary) {
  std::smatch m;
  if (!std::regex_search(summary, m, std::regex(R"(\((\d+) camera \+ (\d+) bounce)"))) return {};
  return {std::stod(m[1]), std::stod(m[2])};
}

class BookPath : public ScratchDirTest {
 protected:
  BookPath() : ScratchDirTest("sphray-book-path-") {}

  // `sphray render -m path` on one thread.
  Pixels sphray_image(const std::string& scene, Rays* rays = nullptr) {
    const std::string out = path("sphray.png");
    const CommandResult r =
        run_sphray("render -m path --threads 1 -s " + scene + " " + kFrame + " --seed 1 -o " + out);
    EXPECT_EQ(r.status, 0) << r.out;
    if (rays != nullptr) *rays = rays_of(r.out);
    return load_pixels(out);
  }

  // The baseline, extra options after the common ones.
  Pixels book_image(const std::string& scene, const std::string& extra = "", Rays* rays = nullptr) {
    const std::string out = path("book.png");
    const CommandResult r = run_program(
        SPHRAY_BOOK_EXE, "-s " + scene + " " + kFrame + " --seed 2 " + extra + " -o " + out);
    EXPECT_EQ(r.status, 0) << r.out;
    if (rays != nullptr) *rays = rays_of(r.out);
    return load_pixels(out);
  }

  // Right within the bounds; each wrong baseline (the book's options that make it wrong)
  // outside twice each.
  void expect_agreement(const std::string& scene, const std::vector<std::string>& wrong) {
    Rays sphray_rays, book_rays;
    const Pixels ours = sphray_image(scene, &sphray_rays);
    const Pixels book = book_image(scene, "", &book_rays);
    ASSERT_EQ(ours.width, kWidth);
    ASSERT_EQ(ours.height, kHeight);
    ASSERT_EQ(book.width, kWidth);
    ASSERT_EQ(book.height, kHeight);
    const Difference right = difference(book, ours);
    std::printf(
        "%s: book against sphray: mean |difference| %.3f, mean difference %+.3f, largest of a "
        "block %.3f\n",
        scene.c_str(), right.mean_absolute, right.mean_signed, right.block_signed);
    EXPECT_LE(right.mean_absolute, kMaxMeanAbsolute);
    EXPECT_LE(std::fabs(right.mean_signed), kMaxMeanSigned);
    EXPECT_LE(right.block_signed, kMaxBlockSigned);

    // The same paths traced alike: the same camera rays, and bounce rays within 2%.
    EXPECT_EQ(book_rays.camera, kCameraRays);
    EXPECT_EQ(sphray_rays.camera, kCameraRays);
    EXPECT_NEAR(book_rays.bounce / sphray_rays.bounce, 1.0, 0.02)
        << "bounce rays: book " << book_rays.bounce << ", sphray " << sphray_rays.bounce;

    for (const std::string& options : wrong) {
      const Pixels wrong_image = book_image(scene, options);
      ASSERT_EQ(wrong_image.width, kWidth) << options;
      ASSERT_EQ(wrong_image.height, kHeight) << options;
      const Difference d = difference(wrong_image, ours);
      std::printf("  with %s for the book: %.3f, %+.3f, %.3f\n", options.c_str(), d.mean_absolute,
                  d.mean_signed, d.block_signed);
      EXPECT_GT(d.mean_absolute, 2 * kMaxMeanAbsolute) << options;
      EXPECT_GT(std::fabs(d.mean_signed), 2 * kMaxMeanSigned) << options;
    }
  }
};

TEST_F(BookPath, AgreesWithSphrayOnThree) {
  expect_agreement("three", {"--max-depth 1"});
}

TEST_F(BookPath, AgreesWithSphrayOnEveryMaterial) {
  expect_agreement(std::string(SPHRAY_SCENES_DIR) + "/materials.json",
                   {"--max-depth 1", "--max-depth 3"});
}

TEST_F(BookPath, RefusesWhatSphrayRefuses) {
  EXPECT_EQ(run_program(SPHRAY_BOOK_EXE, "-s nope.json -o " + path("a.png")).status, 2);
  EXPECT_EQ(run_program(SPHRAY_BOOK_EXE, "-s three -o " + path("a.txt")).status, 2);
  EXPECT_EQ(run_program(SPHRAY_BOOK_EXE, "-s three --spp 0 -o " + path("a.png")).status, 2);
  EXPECT_FALSE(std::filesystem::exists(path("a.png")));
}

}  // namespace
}  // namespace sphray::test
