// The hot steps of the per-ISA kernels (a batch's roots, a node's box test, a walk's step) are
// inlined whatever the size of their unit: GCC's unit-wide growth limit otherwise decides, and
// the masked instantiations pushed the closest hit's inner steps out of line and slowed it
// (docs/decisions.md, "Queries beyond the closest hit (issue 15)").
#pragma once

#if defined(__GNUC__)
#define SPHRAY_FORCE_INLINE [[gnu::always_inline]] inline
// After a lambda's parameter list: the per-batch and per-leaf bodies the queries hand to loops.
#define SPHRAY_FORCE_INLINE_LAMBDA __attribute__((always_inline))
#else
#define SPHRAY_FORCE_INLINE inline
#define SPHRAY_FORCE_INLINE_LAMBDA
#endif
