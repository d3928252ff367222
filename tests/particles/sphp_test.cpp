// The binary particle file read in one process (sphray-mpi's ranks read it in parallel:
// mpi/tests/particle_file_test.cpp): what is written reads back, broken files are refused with
// one line naming the file, and the spheres read answer as those written.
#include <sys/stat.h>

#include <cstring>
#include <iterator>

#include "particle_test_support.hpp"
#include "sphray/particles/particles.hpp"

namespace {

using sphray::particles::test::expect_refused;
using sphray::particles::test::ParticleFileTest;

std::string encode(sphray::SphereView spheres, std::span<const std::uint32_t> order = {}) {
  std::string bytes;
  sphray::particles::write_sphp(
      [&](const void* data, std::size_t size) {
        bytes.append(static_cast<const char*>(data), size);
      },
      spheres, order);
  return bytes;
}

class Sphp : public ParticleFileTest {};

TEST_F(Sphp, WhatIsWrittenReadsBackAndAnswersAsInMemory) {
  const sphray::SphereSoA written = sphray::particles::test::random_spheres(3000);
  const std::string bytes = encode(written.view());
  ASSERT_EQ(bytes.size(), 32u + 16u * 3000u);
  EXPECT_EQ(std::memcmp(bytes.data(), "SPHRAYP\0\1\0\0\0", 12), 0);
  write(path("a.sphp"), bytes);
  const sphray::SphereSoA read = sphray::particles::read_sphp(path("a.sphp"));
  ASSERT_EQ(read.size(), written.size());
  for (std::uint32_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read.center(i).x, written.center(i).x);
    EXPECT_EQ(read.center(i).z, written.center(i).z);
    EXPECT_EQ(read.radius(i), written.radius(i));
  }
  sphray::particles::test::expect_same_hits(read, written);
  // Through the extension-chosen door too, with no colours.
  const sphray::particles::Points points = sphray::particles::read_particle_file(path("a.sphp"));
  EXPECT_EQ(points.spheres.size(), 3000u);
  EXPECT_TRUE(points.colors.empty());
}

TEST_F(Sphp, RecordsFollowTheOrderGiven) {
  const sphray::SphereSoA spheres = sphray::particles::test::random_spheres(3);
  const std::uint32_t order[] = {2, 0, 1};
  write(path("o.sphp"), encode(spheres.view(), order));
  const sphray::particles::SphpFile file(path("o.sphp"));
  EXPECT_EQ(file.count(), 3u);
  sphray::SphereSoA part;
  std::vector<std::uint32_t> ids;
  file.read(1, 3, part, &ids);
  ASSERT_EQ(part.size(), 2u);
  EXPECT_EQ(ids, (std::vector<std::uint32_t>{1, 2}));
  EXPECT_EQ(part.center(0).y, spheres.center(0).y);
  EXPECT_EQ(part.radius(1), spheres.radius(1));
}

TEST_F(Sphp, AnEmptyFileHasNoParticles) {
  write(path("e.sphp"), encode(sphray::SphereSoA().view()));
  EXPECT_EQ(sphray::particles::read_sphp(path("e.sphp")).size(), 0u);
}

TEST_F(Sphp, BrokenFilesAreRefusedNamingTheFile) {
  const std::string good = encode(sphray::particles::test::random_spheres(40).view());
  const auto refused = [&](const std::string& name, const std::string& bytes,
                           const std::string& message) {
    write(path(name), bytes);
    expect_refused([&] { sphray::particles::read_sphp(path(name)); },
                   path(name).string() + ": " + message);
  };
  refused("cut.sphp", good.substr(0, good.size() - 5),
          "truncated: the header says 40 particles, 672 bytes, the file has 667");
  refused("header.sphp", good.substr(0, 20), "truncated: 20 bytes, less than the 32-byte header");
  std::string longer = good + '\0';
  refused("longer.sphp", longer,
          "trailing bytes: the header says 40 particles, 672 bytes, the file has 673");
  std::string bad = good;
  bad[0] = 'X';
  refused("magic.sphp", bad, "not a sphray particle file (no \"SPHRAYP\" magic)");
  bad = good;
  bad[8] = 2;
  refused("version.sphp", bad, "particle file version 2, expected 1");
  bad = good;
  bad[27] = 1;
  refused("reserved.sphp", bad, "corrupt header: reserved fields are not zero");
  bad = good;
  bad[23] = static_cast<char>(0x80);
  refused("count.sphp", bad, "corrupt header: 9223372036854775848 particles, at most 2^32 - 2");
  expect_refused([&] { sphray::particles::read_sphp(path("missing.sphp")); },
                 path("missing.sphp").string() + ": cannot open (No such file or directory)");
  ASSERT_EQ(::mkfifo(path("fifo.sphp").c_str(), 0600), 0);
  expect_refused(
      [&] { sphray::particles::read_sphp(path("fifo.sphp")); },
      path("fifo.sphp").string() + ": not a regular file (a FIFO: ranks read at offsets)");
}

// The largest file the format holds, 2^32 - 2 particles (64 GiB), as a sparse file: only its
// header and last record take disk space. The header's count, the size check and the offset of
// the last record (past 2^36 bytes) are computed without overflow, and that record reads back
// with its id; one particle more is refused before any record is read.
TEST_F(Sphp, TheLargestFileReadsItsLastParticleAtItsOffset) {
  constexpr std::uint64_t kLargest = (std::uint64_t{1} << 32) - 2;
  const sphray::SphereSoA one = sphray::particles::test::random_spheres(1);
  std::string bytes = encode(one.view());
  for (int i = 0; i < 8; ++i)  // the count, little-endian
    bytes[16 + i] = static_cast<char>((kLargest >> (8 * i)) & 0xff);
  const std::filesystem::path file = path("largest.sphp");
  {
    std::ofstream out(file, std::ios::binary);
    out.write(bytes.data(), 32);
    out.seekp(static_cast<std::streamoff>(32 + 16 * (kLargest - 1)));
    out.write(bytes.data() + 32, 16);
    ASSERT_TRUE(out.good()) << "the file system cannot hold a 64 GiB sparse file";
  }
  ASSERT_EQ(std::filesystem::file_size(file), 32 + 16 * kLargest);
  const sphray::particles::SphpFile in(file);
  EXPECT_EQ(in.count(), kLargest);
  sphray::SphereSoA last;
  std::vector<std::uint32_t> ids;
  in.read(kLargest - 1, kLargest, last, &ids);
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(ids, std::vector<std::uint32_t>{0xfffffffdu});  // 2^32 - 3, the last id
  EXPECT_EQ(last.center(0).x, one.center(0).x);
  EXPECT_EQ(last.radius(0), one.radius(0));

  for (int i = 0; i < 4; ++i)  // 2^32 - 1: one too many
    bytes[16 + i] = static_cast<char>(0xff);
  std::filesystem::resize_file(file, 0);
  write(file, bytes.substr(0, 32));
  std::filesystem::resize_file(file, 32 + 16 * (kLargest + 1));
  expect_refused([&] { sphray::particles::SphpFile{file}; },
                 file.string() + ": corrupt header: 4294967295 particles, at most 2^32 - 2");
  EXPECT_THROW(sphray::particles::check_particle_count(kLargest + 1),
               sphray::particles::ParticleError);
  EXPECT_NO_THROW(sphray::particles::check_particle_count(kLargest));
}

}  // namespace
