#pragma once
/// \file
/// Flush-to-zero and denormals-are-zero for the threads that trace or sample VPLs: Embree asks
/// for both (its traversal slows down sharply on denormal inputs), and every thread setting them
/// keeps frames identical across thread counts.

#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#endif

namespace igi {

/// Sets FTZ and DAZ on the current thread for its lifetime, then restores the previous mode.
class FlushDenormals {
 public:
  /// Switches the current thread to flush denormals.
  FlushDenormals() noexcept {
#if defined(__SSE__) || defined(__x86_64__)
    saved_ = _mm_getcsr();
    // 0x8000 is MXCSR's flush-to-zero bit, 0x0040 its denormals-are-zero bit.
    _mm_setcsr(saved_ | 0x8000u | 0x0040u);
#endif
  }
  /// Restores the thread's previous mode.
  ~FlushDenormals() {
#if defined(__SSE__) || defined(__x86_64__)
    _mm_setcsr(saved_);
#endif
  }
  FlushDenormals(const FlushDenormals&) = delete;             ///< Not copyable: one guard per scope.
  FlushDenormals& operator=(const FlushDenormals&) = delete;  ///< Not assignable.

 private:
  unsigned saved_ = 0;
};

}  // namespace igi
