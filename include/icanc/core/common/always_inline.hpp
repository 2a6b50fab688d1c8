// ICANC_ALWAYS_INLINE: for the per-point helpers of the hot loops (decode, fast detector pass 1).
// GCC at -O2 does not always inline them into a template instantiated in another translation
// unit; perf showed FastDetector::keep and Eigen's 3x3 product as a call per point.
#pragma once

#if defined(__GNUC__)
#define ICANC_ALWAYS_INLINE __attribute__((always_inline))
#else
#define ICANC_ALWAYS_INLINE
#endif
