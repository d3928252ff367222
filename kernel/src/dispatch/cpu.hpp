// What this CPU and its operating system can run.
#pragma once

namespace sphray::detail {

struct CpuFeatures {
  bool sse4_2 = false;
  bool avx2_fma = false;  // AVX2 and FMA, with the OS saving ymm state
  bool avx512f = false;   // AVX-512F, with the OS saving zmm and opmask state
  bool neon = false;
};

CpuFeatures detect_cpu();

enum class CpuVendor { other, intel, amd };

/// Who made the CPU and which family and model it is (CPUID leaves 0 and 1, with the extended
/// family and model folded in as the vendors document). {other, 0, 0} off x86.
struct CpuIdentity {
  CpuVendor vendor = CpuVendor::other;
  unsigned family = 0;
  unsigned model = 0;
};

CpuIdentity identify_cpu();

/// The identity CPUID reports: the vendor string's registers of leaf 0 (EBX, EDX, ECX) and EAX of
/// leaf 1 (the signature). Pure, for the tests.
CpuIdentity cpu_identity_from(unsigned ebx, unsigned edx, unsigned ecx, unsigned signature);

}  // namespace sphray::detail
