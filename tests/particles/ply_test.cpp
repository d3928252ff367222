// PLY (.ply): ascii and both binary byte orders with every scalar type, other elements and list
// properties read past wherever they are, colours and radii as the header gives them, a file
// larger than the reader's buffer, write_ply read back bit for bit, the same particles as from
// a .xyz file, and every refusal one line naming the file and the line or byte offset.
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>

#include "particle_test_support.hpp"
#include "sphray/particles/particles.hpp"

namespace {

using sphray::Vec3;
using sphray::particles::parse_ply;
using sphray::particles::Points;
using sphray::particles::read_ply;
using sphray::particles::test::expect_refused;
using sphray::particles::test::ParticleFileTest;

// A binary body built by hand, in the byte order asked for.
struct Body {
  bool big_endian;
  std::string bytes;

  template <typename T>
  Body& put(T value) {
    auto raw = std::bit_cast<std::array<char, sizeof(T)>>(value);
    if (big_endian == (std::endian::native == std::endian::little))
      std::reverse(raw.begin(), raw.end());
    bytes.append(raw.data(), raw.size());
    return *this;
  }
};

class Ply : public ParticleFileTest {
 protected:
  Points read(const std::string& bytes, std::optional<float> radius = std::nullopt) {
    write(path("a.ply"), bytes);
    const Points from_file = read_ply(path("a.ply"), {radius});
    // The in-memory form reads the same.
    const Points from_memory = parse_ply(bytes, "a.ply", {radius});
    EXPECT_EQ(from_memory.spheres.size(), from_file.spheres.size());
    return from_file;
  }
  std::string file() const { return path("a.ply").string(); }
};

void expect_sphere(const Points& p, std::size_t i, Vec3 c, float r) {
  ASSERT_LT(i, p.spheres.size());
  const Vec3 got = p.spheres.center(static_cast<std::uint32_t>(i));
  EXPECT_EQ(got.x, c.x) << "sphere " << i;
  EXPECT_EQ(got.y, c.y) << "sphere " << i;
  EXPECT_EQ(got.z, c.z) << "sphere " << i;
  EXPECT_EQ(p.spheres.radius(static_cast<std::uint32_t>(i)), r) << "sphere " << i;
}

TEST_F(Ply, AsciiWithCommentsFacesAndExtraProperties) {
  const Points p = read(
      "ply\r\n"
      "format ascii 1.0\r\n"
      "comment made by hand\n"
      "obj_info not used\n"
      "element face 2\n"
      "property list uchar int vertex_indices\n"
      "element vertex 3\n"
      "property float x\n"
      "property float nx\n"
      "property double y\n"
      "property int z\n"
      "property float radius\n"
      "element edge 1\n"
      "property int vertex1\n"
      "property int vertex2\n"
      "end_header\n"
      "3 0 1 2\n"
      "4 0 1 2 0\n"
      "1.5 9 -2.25 3 0.5\n"
      "\n"
      "+1e2 0 0 -7 .25\r\n"
      "0 0 1e-3 0 2\n"
      "0 1");  // no final newline
  ASSERT_EQ(p.spheres.size(), 3u);
  EXPECT_TRUE(p.colors.empty());
  expect_sphere(p, 0, {1.5f, -2.25f, 3.0f}, 0.5f);
  expect_sphere(p, 1, {100.0f, 0.0f, -7.0f}, 0.25f);
  expect_sphere(p, 2, {0.0f, static_cast<float>(0.001), 0.0f}, 2.0f);  // a double
}

// One vertex in the order asked, with a face element before it and properties between.
std::string typed_file(bool big_endian) {
  std::string header = std::string("ply\nformat ") +
                       (big_endian ? "binary_big_endian" : "binary_little_endian") +
                       " 1.0\n"
                       "element face 2\n"
                       "property list uchar uint vertex_indices\n"
                       "property char flag\n"
                       "element vertex 2\n"
                       "property short x\n"
                       "property uint8 y\n"
                       "property float64 z\n"
                       "property list ushort float normals\n"
                       "property int32 id\n"
                       "property float32 radius\n"
                       "property uint16 alpha\n"
                       "end_header\n";
  Body b{big_endian, header};
  b.put<std::uint8_t>(3).put<std::uint32_t>(0).put<std::uint32_t>(1).put<std::uint32_t>(2);
  b.put<std::int8_t>(-1);
  b.put<std::uint8_t>(0).put<std::int8_t>(5);  // an empty list
  b.put<std::int16_t>(-300).put<std::uint8_t>(200).put<double>(0.1);
  b.put<std::uint16_t>(2).put<float>(1).put<float>(2);
  b.put<std::int32_t>(-70000).put<float>(0.75f).put<std::uint16_t>(65535);
  b.put<std::int16_t>(7).put<std::uint8_t>(0).put<double>(-1e10);
  b.put<std::uint16_t>(0);
  b.put<std::int32_t>(1).put<float>(3.5f).put<std::uint16_t>(1);
  return b.bytes;
}

TEST_F(Ply, BinaryOfBothByteOrdersWithEveryScalarType) {
  for (bool big : {false, true}) {
    const Points p = read(typed_file(big));
    ASSERT_EQ(p.spheres.size(), 2u) << "big endian " << big;
    expect_sphere(p, 0, {-300.0f, 200.0f, static_cast<float>(0.1)}, 0.75f);
    expect_sphere(p, 1, {7.0f, 0.0f, -1e10f}, 3.5f);
  }
  // The same file in ascii: every type spelt both ways.
  const Points p = read(
      "ply\nformat ascii 1.0\n"
      "element vertex 1\n"
      "property char a\nproperty uchar b\nproperty short c\nproperty ushort d\n"
      "property int e\nproperty uint f\nproperty float g\nproperty double h\n"
      "property int8 x\nproperty uint8 y\nproperty int16 z\nproperty uint16 radius\n"
      "property int32 i\nproperty uint32 j\nproperty float32 k\nproperty float64 l\n"
      "end_header\n"
      "-128 255 -32768 65535 -2147483648 4294967295 1e38 1e308 "
      "-1 2 -3 4 5 6 7 8\n");
  expect_sphere(p, 0, {-1.0f, 2.0f, -3.0f}, 4.0f);
}

TEST_F(Ply, ColoursAsBytesOrUnitFloatsAndARadiusFromScaleOrTheOption) {
  const Points bytes = read(
      "ply\nformat ascii 1.0\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
      "end_header\n0 0 0 255 0 51 9\n1 1 1 0 1 0 9\n",
      0.5f);
  ASSERT_EQ(bytes.colors.size(), 2u);
  EXPECT_EQ(bytes.colors[0].x, 1.0f);
  EXPECT_EQ(bytes.colors[0].z, 0.2f);  // 51 / 255
  EXPECT_EQ(bytes.colors[1].y, 1.0f / 255.0f);
  EXPECT_EQ(bytes.spheres.radius(1), 0.5f);
  Body b{false,
         "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
         "property float x\nproperty float y\nproperty float z\nproperty float scale\n"
         "property float red\nproperty double green\nproperty float blue\nend_header\n"};
  b.put(1.0f).put(2.0f).put(3.0f).put(0.125f).put(0.5f).put(0.25).put(1.0f);
  const Points floats = read(b.bytes, 9.0f);  // a radius in the file wins over the option
  expect_sphere(floats, 0, {1, 2, 3}, 0.125f);
  ASSERT_EQ(floats.colors.size(), 1u);
  EXPECT_EQ(floats.colors[0].x, 0.5f);
  EXPECT_EQ(floats.colors[0].y, 0.25f);
  EXPECT_EQ(floats.colors[0].z, 1.0f);
}

TEST_F(Ply, AFileLargerThanTheBufferWithListsAcrossItsEdges) {
  // 200,000 vertices of 13 to 40 bytes: about 5 MiB, values crossing every 1 MiB boundary.
  constexpr std::uint32_t kCount = 200000;
  Body b{true, "ply\nformat binary_big_endian 1.0\nelement vertex " + std::to_string(kCount) +
                   "\nproperty list uchar float extra\nproperty int x\nproperty float y\n"
                   "property double z\nproperty float radius\nend_header\n"};
  for (std::uint32_t i = 0; i < kCount; ++i) {
    b.put<std::uint8_t>(static_cast<std::uint8_t>(i % 7));
    for (std::uint32_t k = 0; k < i % 7; ++k)
      b.put<float>(-1.0f);
    b.put<std::int32_t>(static_cast<std::int32_t>(i)).put<float>(-0.5f * static_cast<float>(i));
    b.put<double>(i % 3).put<float>(0.25f + static_cast<float>(i % 5));
  }
  const Points p = read(b.bytes);
  ASSERT_EQ(p.spheres.size(), kCount);
  for (std::uint32_t i : {0u, 1u, 65535u, 100001u, kCount - 1}) {
    expect_sphere(p, i,
                  {static_cast<float>(i), -0.5f * static_cast<float>(i), static_cast<float>(i % 3)},
                  0.25f + static_cast<float>(i % 5));
  }
}

TEST_F(Ply, AnAsciiFileLargerThanTheBuffer) {
  // 100,000 lines of 13 to 22 bytes, about 1.9 MiB: a line crosses the 1 MiB boundary.
  constexpr std::uint32_t kCount = 100000;
  std::string text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(kCount) +
                     "\nproperty int x\nproperty float y\nproperty float z\nproperty float radius"
                     "\nend_header\n";
  for (std::uint32_t i = 0; i < kCount; ++i)
    text += std::to_string(i) + " -" + std::to_string(i % 1000) + ".5 0.25 " +
            std::to_string(1 + i % 9) + "\n";
  ASSERT_GT(text.size(), 1u << 20);
  const Points p = read(text);
  ASSERT_EQ(p.spheres.size(), kCount);
  for (std::uint32_t i : {0u, 40000u, 41234u, kCount - 1}) {
    expect_sphere(p, i, {static_cast<float>(i), -0.5f - static_cast<float>(i % 1000), 0.25f},
                  static_cast<float>(1 + i % 9));
  }
}

std::string ply_bytes(const sphray::SphereSoA& spheres, std::span<const Vec3> colors = {}) {
  std::string out;
  sphray::particles::write_ply(
      [&](const void* data, std::size_t size) { out.append(static_cast<const char*>(data), size); },
      spheres.view(), colors);
  return out;
}

TEST_F(Ply, WritePlyReadsBackBitForBit) {
  const sphray::SphereSoA spheres = sphray::particles::test::random_spheres(100000);
  std::vector<Vec3> colors;
  for (std::uint32_t i = 0; i < spheres.size(); ++i)
    colors.push_back({static_cast<float>(i % 256) / 255.0f,  // as the reader divides
                      static_cast<float>(i * 7 % 256) / 255.0f,
                      static_cast<float>(255 - i % 256) / 255.0f});
  const std::string bytes = ply_bytes(spheres, colors);
  // The header, then 19 bytes a vertex: exactly as documented.
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by sphray\nelement vertex 100000\n"
      "property float x\nproperty float y\nproperty float z\nproperty float radius\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  ASSERT_EQ(bytes.size(), header.size() + 19 * spheres.size());
  EXPECT_EQ(static_cast<unsigned char>(bytes[header.size() + 16 + 19 * 300]), 300 % 256);
  const Points p = read(bytes);
  ASSERT_EQ(p.spheres.size(), spheres.size());
  ASSERT_EQ(p.colors.size(), colors.size());
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const Vec3 a = p.spheres.center(i), b = spheres.center(i);
    using Bits = std::array<std::uint32_t, 3>;
    ASSERT_EQ(std::bit_cast<Bits>(a), std::bit_cast<Bits>(b)) << i;
    ASSERT_EQ(std::bit_cast<std::uint32_t>(p.spheres.radius(i)),
              std::bit_cast<std::uint32_t>(spheres.radius(i)));
    ASSERT_EQ(p.colors[i].x, colors[i].x) << i;
    ASSERT_EQ(p.colors[i].y, colors[i].y) << i;
    ASSERT_EQ(p.colors[i].z, colors[i].z) << i;
  }
  sphray::particles::test::expect_same_hits(p.spheres, spheres);
  // Without colours: 16 bytes a vertex and no colour properties.
  const std::string plain = ply_bytes(spheres);
  EXPECT_EQ(plain.find("red"), std::string::npos);
  EXPECT_TRUE(read(plain).colors.empty());
}

TEST_F(Ply, TheSameParticlesAsFromAnXyzFile) {
  const sphray::SphereSoA spheres = sphray::particles::test::random_spheres(2000, 5);
  std::string xyz, ascii =
                       "ply\nformat ascii 1.0\nelement vertex 2000\nproperty float x\n"
                       "property float y\nproperty float z\nproperty float radius\n"
                       "end_header\n";
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    char line[128];
    const Vec3 c = spheres.center(i);
    std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g\n", c.x, c.y, c.z, spheres.radius(i));
    xyz += line;
    ascii += line;
  }
  write(path("a.xyz"), xyz);
  const Points from_xyz = sphray::particles::read_points(path("a.xyz"));
  for (const std::string& bytes : {ascii, ply_bytes(spheres)}) {
    const Points p = read(bytes);
    ASSERT_EQ(p.spheres.size(), from_xyz.spheres.size());
    for (std::uint32_t i = 0; i < spheres.size(); ++i) {
      ASSERT_EQ(p.spheres.center(i).x, from_xyz.spheres.center(i).x) << i;
      ASSERT_EQ(p.spheres.center(i).y, from_xyz.spheres.center(i).y) << i;
      ASSERT_EQ(p.spheres.center(i).z, from_xyz.spheres.center(i).z) << i;
      ASSERT_EQ(p.spheres.radius(i), from_xyz.spheres.radius(i)) << i;
    }
    sphray::particles::test::expect_same_hits(p.spheres, spheres);
  }
}

struct Refusal {
  std::string bytes;
  std::string message;  // after the file's name
  std::optional<float> radius = std::nullopt;
};

const std::string kFaceHeader =
    "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int v\nelement vertex 1\n"
    "property float x\nproperty float y\nproperty float z\nend_header\n";  // 9 lines

const std::string kXyzHeader =
    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
    "property float z\nproperty float radius\nend_header\n";  // 8 lines

TEST_F(Ply, BadHeadersAreRefusedNamingTheLine) {
  const Refusal refusals[] = {
      {"PLY\n", ":1: expected 'ply' (the first line of a PLY file), got \"PLY\""},
      {"ply\nformat ascii 2.0\n",
       ":2: expected 'format ascii 1.0', 'format binary_little_endian 1.0' or 'format "
       "binary_big_endian 1.0', got \"format ascii 2.0\""},
      {"ply\nelement vertex 1\n", ":2: expected a 'format' line before the elements"},
      {"ply\nformat ascii 1.0\nelement vertex -1\n",
       ":3: expected 'element NAME COUNT', got \"element vertex -1\""},
      {"ply\nformat ascii 1.0\nelement vertex 99999999999999999999\n",
       ":3: expected 'element NAME COUNT', got \"element vertex 99999999999999999999\""},
      {"ply\nformat ascii 1.0\nproperty float x\n",
       ":3: expected 'element NAME COUNT' before 'property', got \"property float x\""},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float\n",
       ":4: expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME', got "
       "\"property float\""},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float16 x\n",
       ":4: expected a PLY type (char, uchar, short, ushort, int, uint, float, double or int8, "
       "uint8, int16, uint16, int32, uint32, float32, float64), got \"float16\""},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty list float int v\n",
       ":4: expected an integer type for the count of list v, got \"float\""},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n",
       ":4: expected property x of element vertex to be a scalar, got a list"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\n",
       ":5: expected each property of element vertex named once, got \"x\" twice"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float radius\nproperty float scale\n",
       ":5: expected one of properties radius and scale in element vertex, got both"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\n",
       ":4: expected one element vertex, got a second"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nvertex 1 2 3\n",
       ":5: expected 'element', 'property', 'comment', 'obj_info' or 'end_header', got "
       "\"vertex 1 2 3\""},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
       ":5: expected 'end_header', got the end of the file"},
      {"ply\nformat ascii 1.0\nelement face 1\nend_header\n",
       ":4: expected an element vertex (the particles), the header has none"},
      {"ply\nformat ascii 1.0\ncomment\nelement vertex 1\nproperty float x\nproperty float y\n"
       "end_header\n",
       ":4: expected properties x, y and z in element vertex"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n1 2 3\n",
       ":3: expected a property radius (or scale) in element vertex, or a radius given for the "
       "file (sphray render --radius R)"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nproperty uchar red\nend_header\n1 2 3 4\n",
       ":3: expected properties red, green and blue in element vertex together, or none", 1.0f},
      {"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n",
       ": expected particles, the file has none", 1.0f},
      {"ply\nformat ascii 1.0\nelement vertex 4294967295\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n",
       ":3: expected at most 2^32 - 2 particles, got 4294967295", 1.0f},
      {"ply\ncomment " + std::string(5000, 'a') + "\n", ":2: expected lines of at most 4096 bytes"},
      {"ply\nformat ascii 1.0\nend_header\n",
       ":3: expected an element vertex (the particles), "
       "the header has none"},
      {"1 2 3\n", ":1: expected 'ply' (the first line of a PLY file), got \"1 2 3\""},
      {"", ":1: expected 'ply' (the first line of a PLY file), got \"\""},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n",
       ":5: expected 'end_header', "
       "got the end of the file"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n1 2 3\n",
       ": expected the radius given for the file to be positive and at most 1e17, got -1", -1.0f},
  };
  for (const Refusal& r : refusals) {
    write(path("a.ply"), r.bytes);
    expect_refused([&] { read_ply(path("a.ply"), {r.radius}); }, file() + r.message);
    expect_refused([&] { parse_ply(r.bytes, "mem.ply", {r.radius}); }, "mem.ply" + r.message);
  }
}

TEST_F(Ply, BadAsciiBodiesAreRefusedNamingTheLine) {
  const Refusal refusals[] = {
      {kXyzHeader + "1 2 3 1\n1 2 x 1\n",
       ":10: expected property z of vertex 1 to be a number, got \"x\""},
      {kXyzHeader + "1 2 3 1\n1000000 2 3\n",
       ":10: expected a value for property radius of vertex 1, got the end of the line"},
      {kXyzHeader + "1 2 3 1 5\n1 2 3 1\n",
       ":9: expected the line of vertex 0 to end after its 4 values, got \"5\""},
      {kXyzHeader + "1 2 3 1000000000000\n",
       ":10: expected vertex 1 of 2 (a line each), got the end of the file"},
      {kXyzHeader + "1 2 3 1\n1 2 3 1\n1 2 3 1\n",
       ":11: expected the end of the file after the last element, got \"1 2 3 1\""},
      {kXyzHeader + "1 2 3 0\n1 2 3 1\n",
       ":9: expected property radius of vertex 0 to be positive, got \"0\""},
      {kXyzHeader + "1 2 nan 1\n1 2 3 1\n",
       ":9: expected property z of vertex 0 to be finite, got \"nan\""},
      {kXyzHeader + "1 2 1e18 1\n1 2 3 1\n",
       ":9: expected property z of vertex 0 at most 1e17 in magnitude, got \"1e18\""},
      {kXyzHeader + "1 2 1e39 1\n1 2 3 1\n",
       ":9: expected property z of vertex 0 within float's range, got \"1e39\""},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
       "end_header\n0 0 0 1 2 256\n",
       ":11: expected property blue of vertex 0 to be a uchar, got \"256\"", 1.0f},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nproperty float red\nproperty float green\nproperty float blue\n"
       "end_header\n0 0 0 1 2 0\n",
       ":11: expected property green of vertex 0 in [0, 1] (a floating-point colour), got \"2\"",
       1.0f},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "property float z\nproperty short red\nproperty short green\nproperty short blue\n"
       "end_header\n0 0 0 -1 2 0\n",
       ":11: expected property red of vertex 0 in 0 to 255 (an integer colour), got \"-1\"", 1.0f},
      {kFaceHeader + "3 1 2\n0 0 0\n",
       ":10: expected a value for property v of face 0, got the end of the line", 1.0f},
      {kFaceHeader + "-1\n0 0 0\n", ":10: expected property v of face 0 to be a uchar, got \"-1\"",
       1.0f},
      // A count that cannot fit the file: refused at its element's line, before any allocation.
      {"ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n1 2 3\n",
       ":3: expected 100000000 vertex elements to fit the file, at least 600000000 bytes after "
       "the header with those before, got 6",
       1.0f},
      {kXyzHeader + std::string(5000, ' ') + "\n", ":9: expected lines of at most 4096 bytes"},
  };
  for (const Refusal& r : refusals) {
    write(path("a.ply"), r.bytes);
    expect_refused([&] { read_ply(path("a.ply"), {r.radius}); }, file() + r.message);
  }
}

TEST_F(Ply, BadBinaryBodiesAreRefusedNamingTheByte) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar int v\n"
      "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "property float radius\nend_header\n";
  const std::size_t h = header.size();
  const auto body = [&] { return Body{false, header}; };
  const auto face = [&](Body b) { return b.put<std::uint8_t>(1).put<std::int32_t>(0); };
  const auto vertex = [&](Body b, float z, float r) { return b.put(1.0f).put(2.0f).put(z).put(r); };
  const std::string good = vertex(vertex(face(body()), 3, 1), 3, 1).bytes;
  const std::string at = ": byte ";
  // A list count as a char, negative.
  const std::string signed_count =
      "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list char int v\n"
      "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  const Refusal refusals[] = {
      {good.substr(0, good.size() - 3),
       at + std::to_string(good.size() - 3) + " (vertex 1): file ends, expected 3 more bytes"},
      {signed_count + std::string("\xff", 1) + std::string(12, '\0'),
       at + std::to_string(signed_count.size()) +
           " (face 0): expected the count of list v to be >= 0, got -1",
       1.0f},
      // A list longer than the file.
      {vertex(vertex(body().put<std::uint8_t>(200), 3, 1), 3, 1).bytes,
       at + std::to_string(h + 33) + " (face 0): file ends, expected 768 more bytes"},
      {vertex(vertex(face(body()), NAN, 1), 3, 1).bytes,
       at + std::to_string(h + 13) + " (vertex 0): expected property z to be finite, got nan"},
      {vertex(vertex(face(body()), 3, 1), 3, -2).bytes,
       at + std::to_string(h + 5 + 16 + 12) +
           " (vertex 1): expected property radius to be positive, got -2"},
      {vertex(vertex(face(body()), 3, 1), 3, 1).put<char>(0).bytes,
       at + std::to_string(h + 37) +
           ": expected the end of the file after the last element, got 1 more bytes"},
      // The face's list count and both vertices cannot be fewer than 33 bytes.
      {good.substr(0, h + 32),
       ":5: expected 2 vertex elements to fit the file, at least 33 bytes after the header with "
       "those before, got 32"},
  };
  for (const Refusal& r : refusals) {
    write(path("a.ply"), r.bytes);
    expect_refused([&] { read_ply(path("a.ply"), {r.radius}); }, file() + r.message);
  }
  // A double too large for float, big-endian.
  Body big{true,
           "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty double x\n"
           "property double y\nproperty double z\nend_header\n"};
  big.put(0.0).put(1e300).put(0.0);
  expect_refused([&] { parse_ply(big.bytes, "big.ply", {1.0f}); },
                 "big.ply: byte " + std::to_string(big.bytes.size() - 16) +
                     " (vertex 0): expected property y at most 1e17 in magnitude, got 1e+300");
}

TEST_F(Ply, OnlyRegularFilesAreRead) {
  expect_refused([&] { read_ply(dir_); },
                 dir_.string() + ": expected a particle file, got a directory");
  ASSERT_EQ(::mkfifo(path("fifo.ply").c_str(), 0600), 0);
  expect_refused([&] { read_ply(path("fifo.ply")); },
                 path("fifo.ply").string() + ": expected a regular file");
  expect_refused(
      [&] { read_ply(path("none.ply")); },
      path("none.ply").string() + ": cannot read the particle file (No such file or directory)");
  // The extension chooses the reader.
  write(path("b.PLY"), ply_bytes(sphray::particles::test::random_spheres(3)));
  EXPECT_TRUE(sphray::particles::is_particle_file(path("b.PLY")));
  EXPECT_EQ(sphray::particles::read_particle_file(path("b.PLY")).spheres.size(), 3u);
}

}  // namespace
