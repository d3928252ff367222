// The tree's instruction set per CPU (dispatch/tree_isa_rule.hpp) as a pure function of the
// CPU's identity and what runs on it; the identity's decoding from CPUID; and bvh_isa(), the
// choice this process made with them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "dispatch/cpu.hpp"
#include "dispatch/tree_isa_rule.hpp"
#include "sphray/bvh.hpp"
#include "sphray/isa.hpp"
#include "sphray/spheres.hpp"

namespace sphray::detail {
namespace {

const std::vector<Isa> kAvx512Machine = {Isa::avx512, Isa::avx2, Isa::sse4_2, Isa::scalar};
const std::vector<Isa> kAvx2Machine = {Isa::avx2, Isa::sse4_2, Isa::scalar};

constexpr CpuIdentity kZen5{CpuVendor::amd, 0x1a, 0x02};  // EPYC 9005 "Turin"
constexpr CpuIdentity kZen4{CpuVendor::amd, 0x19, 0x11};  // EPYC 9004 "Genoa"
constexpr CpuIdentity kZen2{CpuVendor::amd, 0x17, 0x31};
constexpr CpuIdentity kSapphireRapids{CpuVendor::intel, 0x6, 0x8f};
constexpr CpuIdentity kUnknown{CpuVendor::other, 0x1a, 0x02};

constexpr std::size_t kMany = std::size_t{1} << 20;

TEST(TreeIsaRule, Zen5KeepsTheSixteenWideTreeAtEverySize) {
  for (const std::size_t n : {std::size_t{0}, std::size_t{512}, std::size_t{2048}, kMany})
    EXPECT_EQ(tree_isa_for(kZen5, kAvx512Machine, n), Isa::avx512) << n;
}

// Zen 4 runs a 512-bit instruction as two 256-bit halves: the 8-wide tree wins below 1024
// spheres, the 16-wide one from there (docs/decisions.md).
TEST(TreeIsaRule, Zen4TakesTheEightWideTreeBelow1024Spheres) {
  EXPECT_EQ(tree_isa_for(kZen4, kAvx512Machine, 0), Isa::avx2);
  EXPECT_EQ(tree_isa_for(kZen4, kAvx512Machine, 486), Isa::avx2);
  EXPECT_EQ(tree_isa_for(kZen4, kAvx512Machine, 1023), Isa::avx2);
  EXPECT_EQ(tree_isa_for(kZen4, kAvx512Machine, 1024), Isa::avx512);
  EXPECT_EQ(tree_isa_for(kZen4, kAvx512Machine, kMany), Isa::avx512);
}

TEST(TreeIsaRule, FamiliesWithoutARuleTakeTheWidest) {
  EXPECT_EQ(tree_isa_for(kSapphireRapids, kAvx512Machine, 100), Isa::avx512);
  EXPECT_EQ(tree_isa_for(kSapphireRapids, kAvx2Machine, kMany), Isa::avx2);
  EXPECT_EQ(tree_isa_for(kZen2, kAvx2Machine, 100), Isa::avx2);
  EXPECT_EQ(tree_isa_for(kUnknown, kAvx512Machine, 100), Isa::avx512);
}

TEST(TreeIsaRule, NeverChoosesWhatCannotRun) {
  // A Zen 4 or 5 whose OS does not save the zmm state, or a build without avx512.
  EXPECT_EQ(tree_isa_for(kZen5, kAvx2Machine, kMany), Isa::avx2);
  EXPECT_EQ(tree_isa_for(kZen4, kAvx2Machine, kMany), Isa::avx2);
  const std::vector<Isa> sse_only = {Isa::sse4_2, Isa::scalar};
  EXPECT_EQ(tree_isa_for(kZen5, sse_only, kMany), Isa::sse4_2);
  EXPECT_EQ(tree_isa_for(kZen4, sse_only, 100), Isa::sse4_2);
  const std::vector<Isa> scalar_only = {Isa::scalar};
  EXPECT_EQ(tree_isa_for(kZen5, scalar_only, kMany), Isa::scalar);
}

// CPUID leaf 0's vendor string as the three registers hold it (EBX, EDX, ECX).
struct VendorRegisters {
  unsigned ebx, edx, ecx;
};
VendorRegisters vendor_registers(const char (&name)[13]) {
  VendorRegisters r{};
  std::memcpy(&r.ebx, name, 4);
  std::memcpy(&r.edx, name + 4, 4);
  std::memcpy(&r.ecx, name + 8, 4);
  return r;
}

CpuIdentity decode(const char (&vendor)[13], unsigned signature) {
  const VendorRegisters r = vendor_registers(vendor);
  return cpu_identity_from(r.ebx, r.edx, r.ecx, signature);
}

void expect_identity(const CpuIdentity& got, CpuVendor vendor, unsigned family, unsigned model) {
  EXPECT_EQ(got.vendor, vendor);
  EXPECT_EQ(got.family, family);
  EXPECT_EQ(got.model, model);
}

// Signatures (CPUID leaf 1 EAX) of real parts: stepping, model, family, extended model and
// extended family in their bit fields.
TEST(CpuIdentity, DecodesVendorFamilyAndModel) {
  expect_identity(decode("AuthenticAMD", 0x00B00F21), CpuVendor::amd, 0x1a, 0x02);   // Zen 5
  expect_identity(decode("AuthenticAMD", 0x00A10F11), CpuVendor::amd, 0x19, 0x11);   // Zen 4
  expect_identity(decode("GenuineIntel", 0x000806F8), CpuVendor::intel, 0x6, 0x8f);  // SPR
  // Family 5 takes neither extension field.
  expect_identity(decode("GenuineIntel", 0x00FF0543), CpuVendor::intel, 0x5, 0x4);
  EXPECT_EQ(decode("HygonGenuine", 0x00900F02).vendor, CpuVendor::other);
}

// This machine's identity against the kernel's own report in /proc/cpuinfo (Linux, x86).
TEST(CpuIdentity, MatchesProcCpuinfo) {
  std::ifstream in("/proc/cpuinfo");
  std::string line, vendor;
  long family = -1, model = -1;
  while (std::getline(in, line) && (vendor.empty() || family < 0 || model < 0)) {
    const auto value = [&] { return line.substr(line.find(':') + 2); };
    if (line.rfind("vendor_id", 0) == 0) vendor = value();
    if (line.rfind("cpu family", 0) == 0) family = std::stol(value());
    if (line.rfind("model\t", 0) == 0) model = std::stol(value());
  }
  if (vendor.empty() || family < 0 || model < 0) GTEST_SKIP() << "no x86 /proc/cpuinfo here";
  const CpuIdentity id = identify_cpu();
  const CpuVendor expected = vendor == "AuthenticAMD"   ? CpuVendor::amd
                             : vendor == "GenuineIntel" ? CpuVendor::intel
                                                        : CpuVendor::other;
  expect_identity(id, expected, static_cast<unsigned>(family), static_cast<unsigned>(model));
}

// The process's choice: SPHRAY_ISA when honoured, the rule on this machine's identity otherwise;
// and a tree built without an instruction set is laid out for it.
TEST(TreeIsaRule, BvhIsaFollowsTheOverrideOrTheRule) {
  const char* requested = std::getenv("SPHRAY_ISA");
  const IsaChoice choice = choose_isa(requested);
  const bool honoured = requested != nullptr && *requested != '\0' && choice.message.empty();
  const std::span<const Isa> isas = supported_isas();
  for (const std::size_t n : {std::size_t{0}, std::size_t{512}, std::size_t{2048}, kMany}) {
    const Isa expected = honoured ? choice.isa : tree_isa_for(identify_cpu(), isas, n);
    EXPECT_EQ(bvh_isa(n), expected) << n;
    EXPECT_NE(std::find(isas.begin(), isas.end(), bvh_isa(n)), isas.end()) << n;
  }
  EXPECT_EQ(bvh_isa(), bvh_isa(std::numeric_limits<std::size_t>::max()));
  EXPECT_EQ(SphereBVH(SphereView{nullptr, nullptr, nullptr, nullptr, 0, 0}).isa(), bvh_isa(0));
  SphereSoA many;
  for (int i = 0; i < 3000; ++i)
    many.add({static_cast<float>(i), 0, 0}, 0.25f);
  EXPECT_EQ(SphereBVH(many.view()).isa(), bvh_isa(3000));
}

}  // namespace
}  // namespace sphray::detail
