/* SPHRAY_API marks what libsphray.so exports. The library is compiled with hidden visibility
 * (and a linker version script, kernel/cmake/libsphray.map), so that only the sphray_ C
 * functions of sphray.h and the public sphray:: C++ API are part of its ABI; everything else,
 * the per-instruction-set kernels, xsimd, oneTBB and the standard library's template
 * instantiations, stays inside. C and C++ alike include this header. */
#ifndef SPHRAY_API_H
#define SPHRAY_API_H

#if defined(__GNUC__) || defined(__clang__)
#define SPHRAY_API __attribute__((visibility("default")))
#else
#define SPHRAY_API
#endif

#endif /* SPHRAY_API_H */
