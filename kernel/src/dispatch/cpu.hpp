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

}  // namespace sphray::detail
