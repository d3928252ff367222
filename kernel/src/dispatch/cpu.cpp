#include "dispatch/cpu.hpp"

#include <cstdint>

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace sphray::detail {

#if defined(__x86_64__) || defined(__i386__)
namespace {

// XCR0, the register state the OS saves on a context switch. A CPU may report AVX or AVX-512
// through CPUID while the OS has not enabled its registers (xsimd 8.1 checks CPUID only), and
// using them then faults: both the feature bits and these state bits are required.
std::uint64_t os_saved_state() {
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!__get_cpuid(1, &eax, &ebx, &ecx, &edx)) return 0;
  if (!(ecx & bit_OSXSAVE)) return 0;
  std::uint32_t lo = 0, hi = 0;
  __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  return (static_cast<std::uint64_t>(hi) << 32) | lo;
}

constexpr std::uint64_t kXmmYmm = 0x6;      // SSE and AVX state
constexpr std::uint64_t kOpmaskZmm = 0xe0;  // opmask, upper zmm0-15, zmm16-31

}  // namespace

CpuFeatures detect_cpu() {
  __builtin_cpu_init();
  const std::uint64_t xcr0 = os_saved_state();
  const bool avx_os = (xcr0 & kXmmYmm) == kXmmYmm;
  const bool avx512_os = avx_os && (xcr0 & kOpmaskZmm) == kOpmaskZmm;
  CpuFeatures f;
  f.sse4_2 = __builtin_cpu_supports("sse4.2");
  f.avx2_fma = avx_os && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  f.avx512f = avx512_os && f.avx2_fma && __builtin_cpu_supports("avx512f");
  return f;
}

CpuIdentity identify_cpu() {
  unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
  if (!__get_cpuid(0, &eax, &ebx, &ecx, &edx)) return {};
  const unsigned vendor_ebx = ebx, vendor_edx = edx, vendor_ecx = ecx;
  if (!__get_cpuid(1, &eax, &ebx, &ecx, &edx)) eax = 0;
  return cpu_identity_from(vendor_ebx, vendor_edx, vendor_ecx, eax);
}
#elif defined(__aarch64__)
CpuIdentity identify_cpu() {
  return {};
}

CpuFeatures detect_cpu() {
  CpuFeatures f;
  f.neon = true;  // part of the AArch64 baseline
  return f;
}
#else
CpuFeatures detect_cpu() {
  return {};
}

CpuIdentity identify_cpu() {
  return {};
}
#endif

CpuIdentity cpu_identity_from(unsigned ebx, unsigned edx, unsigned ecx, unsigned signature) {
  CpuIdentity id;
  // "GenuineIntel" and "AuthenticAMD", four characters per register, little-endian.
  if (ebx == 0x756e6547 && edx == 0x49656e69 && ecx == 0x6c65746e) id.vendor = CpuVendor::intel;
  if (ebx == 0x68747541 && edx == 0x69746e65 && ecx == 0x444d4163) id.vendor = CpuVendor::amd;
  // The extended family counts only when the base family is 0xF, the extended model only for
  // families 0x6 and 0xF (Intel SDM and AMD APM, CPUID leaf 1).
  const unsigned base_family = (signature >> 8) & 0xf, base_model = (signature >> 4) & 0xf;
  const unsigned ext_family = (signature >> 20) & 0xff, ext_model = (signature >> 16) & 0xf;
  id.family = base_family == 0xf ? base_family + ext_family : base_family;
  id.model = base_family == 0xf || base_family == 0x6 ? (ext_model << 4) + base_model : base_model;
  return id;
}

}  // namespace sphray::detail
