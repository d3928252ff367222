// The particle file, read by every rank in parallel: the runs the ranks read make up the file,
// a scene built from them answers as the single-process kernel over the file's spheres, and a
// broken file is refused on every rank alike (the test would hang, and time out, if one rank
// went on to a reduction the others never reach).
#include <gtest/gtest.h>
#include <mpi.h>
#include <sys/stat.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "sphray/mpi/distributed_scene.hpp"
#include "sphray/mpi/particle_file.hpp"
#include "sphray/sphray.hpp"
#include "world.hpp"

namespace {

using sphray::mpi::test::rank;
using sphray::mpi::test::ranks;

using sphray::mpi::ParticleFileError;

// A file name of this run's own (every rank the same), in the working directory.
std::filesystem::path scratch(const std::string& name) {
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  return std::filesystem::current_path() / ("particles-" + std::to_string(ranks) + "-" + name);
}

// Rank 0 writes bytes to file; every rank waits until it has.
void write_on_rank0(const std::filesystem::path& file, const std::vector<unsigned char>& bytes) {
  if (rank() == 0) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// The particle file of spheres, written with the library's encoder to an ordinary stream.
void write_file(const std::filesystem::path& file, sphray::SphereView spheres) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  sphray::mpi::write_particles(
      [&](const void* data, std::size_t size) {
        out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
      },
      spheres);
}

std::vector<unsigned char> read_all(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The format as the header documents it, decoded here independently of the library: the
// particles of a well-formed file, in file order.
sphray::SphereSoA decode(const std::vector<unsigned char>& bytes) {
  const auto le32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i)
      v = v << 8 | bytes[at + static_cast<std::size_t>(i)];
    return v;
  };
  std::uint64_t count = le32(16) | std::uint64_t{le32(20)} << 32;
  sphray::SphereSoA spheres;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::size_t at = 32 + 16 * i;
    spheres.add({std::bit_cast<float>(le32(at)), std::bit_cast<float>(le32(at + 4)),
                 std::bit_cast<float>(le32(at + 8))},
                std::bit_cast<float>(le32(at + 12)));
  }
  return spheres;
}

sphray::SphereSoA random_spheres(std::size_t n) {
  std::mt19937 rng(11);
  const auto u = [&](float lo, float hi) {
    return lo + (hi - lo) * static_cast<float>(rng() >> 8) * 0x1p-24f;
  };
  sphray::SphereSoA spheres;
  for (std::size_t i = 0; i < n; ++i)
    spheres.add({u(-5, 5), u(-5, 5), u(-5, 5)}, u(0.05f, 0.4f));
  return spheres;
}

TEST(MpiParticleFile, RanksReadTheWholeFileAndAnswerAsOneProcess) {
  const auto file = scratch("good.sphp");
  const sphray::SphereSoA written = random_spheres(2500);
  if (rank() == 0) write_file(file, written.view());
  MPI_Barrier(MPI_COMM_WORLD);
  const std::vector<unsigned char> bytes = read_all(file);
  ASSERT_EQ(bytes.size(), 32u + 16u * 2500u);
  EXPECT_EQ(std::memcmp(bytes.data(), "SPHRAYP\0", 8), 0);
  const sphray::SphereSoA all = decode(bytes);

  const sphray::mpi::ParticleShare share = sphray::mpi::read_particle_share(MPI_COMM_WORLD, file);
  EXPECT_EQ(share.total, 2500u);
  for (std::size_t k = 0; k < share.ids.size(); ++k) {
    const std::uint32_t id = share.ids[k];
    EXPECT_EQ(share.spheres.center(static_cast<std::uint32_t>(k)).x, all.center(id).x);
    EXPECT_EQ(share.spheres.radius(static_cast<std::uint32_t>(k)), all.radius(id));
  }
  unsigned long long mine = share.ids.size(), sum = 0;
  MPI_Allreduce(&mine, &sum, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(sum, 2500u);

  const sphray::mpi::DistributedScene scene(MPI_COMM_WORLD, share.spheres.view(), share.ids);
  std::mt19937 rng(12);
  std::vector<sphray::Ray> rays(1000);
  for (sphray::Ray& ray : rays) {
    ray.origin = {0, 0, 20};
    ray.dir = all.center(static_cast<std::uint32_t>(rng() % all.size())) - ray.origin;
  }
  std::vector<sphray::Hit> hits(rays.size());
  scene.intersect(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const sphray::Hit expected = sphray::scalar::intersect(all.view(), rays[i]);
    EXPECT_EQ(hits[i].id, expected.id) << "ray " << i;
    EXPECT_EQ(std::bit_cast<std::uint32_t>(hits[i].t), std::bit_cast<std::uint32_t>(expected.t));
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) std::filesystem::remove(file);
}

// A text file has no offsets to read at: every rank reads it whole and keeps the same run of it
// as of the .sphp file of the same particles; together the ranks hold every particle once.
TEST(MpiParticleFile, RanksReadTheirRunOfATextFile) {
  const auto file = scratch("points.xyz");
  const int n = 1001;
  if (rank() == 0) {
    std::ofstream out(file);
    for (int i = 0; i < n; ++i)  // exact in float and in decimal
      out << i << " " << -i << " " << 0.5 * i << " " << 0.25 + 0.125 * (i % 4) << "\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const sphray::mpi::ParticleShare share = sphray::mpi::read_particle_share(MPI_COMM_WORLD, file);
  EXPECT_EQ(share.total, static_cast<std::uint64_t>(n));
  const auto count = static_cast<std::uint64_t>(ranks());
  const auto me = static_cast<std::uint64_t>(rank());
  ASSERT_EQ(share.ids.size(), n * (me + 1) / count - n * me / count);
  for (std::size_t k = 0; k < share.ids.size(); ++k) {
    const std::uint32_t id = share.ids[k];
    EXPECT_EQ(id, n * me / count + k);
    const sphray::Vec3 c = share.spheres.center(static_cast<std::uint32_t>(k));
    EXPECT_EQ(c.x, static_cast<float>(id));
    EXPECT_EQ(c.y, -static_cast<float>(id));
    EXPECT_EQ(c.z, 0.5f * static_cast<float>(id));
    EXPECT_EQ(share.spheres.radius(static_cast<std::uint32_t>(k)), 0.25f + 0.125f * (id % 4));
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) std::filesystem::remove(file);
}

// A broken file: every rank throws ParticleFileError naming the problem.
void expect_refused(const std::string& name, const std::vector<unsigned char>& bytes,
                    const std::string& words) {
  const auto file = scratch(name);
  write_on_rank0(file, bytes);
  try {
    sphray::mpi::read_particle_share(MPI_COMM_WORLD, file);
    ADD_FAILURE() << name << ": read without an error";
  } catch (const ParticleFileError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) std::filesystem::remove(file);
}

TEST(MpiParticleFile, BrokenFilesAreRefusedOnEveryRank) {
  const auto good_file = scratch("source.sphp");
  if (rank() == 0) write_file(good_file, random_spheres(40).view());
  MPI_Barrier(MPI_COMM_WORLD);
  const std::vector<unsigned char> good = read_all(good_file);
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) std::filesystem::remove(good_file);

  std::vector<unsigned char> cut(good.begin(), good.end() - 5);
  expect_refused("cut.sphp", cut, "truncated");
  expect_refused("header.sphp", {good.begin(), good.begin() + 20}, "truncated");
  expect_refused("empty.sphp", {}, "truncated");
  std::vector<unsigned char> longer = good;
  longer.push_back(0);
  expect_refused("longer.sphp", longer, "trailing bytes");
  std::vector<unsigned char> magic = good;
  magic[0] = 'X';
  expect_refused("magic.sphp", magic, "not a sphray particle file");
  std::vector<unsigned char> version = good;
  version[8] = 2;
  expect_refused("version.sphp", version, "version 2");
  std::vector<unsigned char> reserved = good;
  reserved[27] = 1;
  expect_refused("reserved.sphp", reserved, "reserved");
  std::vector<unsigned char> count = good;
  count[23] = 0x80;  // 2^63 particles: would overflow a size computed carelessly
  expect_refused("count.sphp", count, "at most 2^32 - 2");

  try {
    sphray::mpi::read_particle_share(MPI_COMM_WORLD, scratch("missing.sphp"));
    ADD_FAILURE() << "a missing file was read";
  } catch (const ParticleFileError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

// A FIFO has no offsets to read at: it is refused at once, where opening it for reading would
// wait for a writer for ever (ctest's timeout would catch that).
TEST(MpiParticleFile, AFifoIsRefusedWithoutWaiting) {
  const auto fifo = scratch("fifo.sphp");
  if (rank() == 0) {
    std::filesystem::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    sphray::mpi::read_particle_share(MPI_COMM_WORLD, fifo);
    ADD_FAILURE() << "a FIFO was read";
  } catch (const ParticleFileError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file (a FIFO"), std::string::npos)
        << e.what();
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank() == 0) std::filesystem::remove(fifo);
}

// Ranks whose copies of a file differ (node-local files, a file replaced as the job starts):
// every rank refuses, naming what differs, where they would read runs of different files.
TEST(MpiParticleFile, RanksThatReadDifferentFilesAllRefuse) {
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (ranks < 2) GTEST_SKIP() << "needs two ranks";
  // Each rank its own file: the last rank's differs from the others' in its count, or (second
  // round) in one coordinate of every particle, with the same count.
  for (const bool same_count : {false, true}) {
    const bool odd = rank() == ranks - 1;
    sphray::SphereSoA spheres = random_spheres(odd && !same_count ? 301 : 300);
    if (odd && same_count) {
      sphray::SphereSoA moved;
      for (std::uint32_t i = 0; i < spheres.size(); ++i) {
        moved.add(spheres.center(i) + sphray::Vec3{0.5f, 0, 0}, spheres.radius(i));
      }
      spheres = moved;
    }
    const auto file = scratch("rank" + std::to_string(rank()) + ".sphp");
    write_file(file, spheres.view());
    try {
      sphray::mpi::read_particle_share(MPI_COMM_WORLD, file);
      ADD_FAILURE() << "rank " << rank() << " read a file the others do not have";
    } catch (const ParticleFileError& e) {
      const std::string words =
          same_count ? "the ranks read different files (they differ in the hash of the header"
                     : "the ranks read different files (they differ in the particle count "
                       "(300 to 301), the hash";
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    std::filesystem::remove(file);
    MPI_Barrier(MPI_COMM_WORLD);
  }
}

}  // namespace
