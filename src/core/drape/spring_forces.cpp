#include "virtual_tryon/core/drape/spring_forces.h"

#include <cmath>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define VT_X86 1
#endif

namespace virtual_tryon {
namespace {

// Springs [begin, end) one at a time.
void addScalar(const SpringArrays& s, std::size_t begin, std::size_t end, const double* x, double* f,
               double limit, std::vector<int>& over) {
  for (std::size_t i = begin; i < end; ++i) {
    const double* xa = x + 4 * s.a[i];
    const double* xb = x + 4 * s.b[i];
    const double dx = xb[0] - xa[0], dy = xb[1] - xa[1], dz = xb[2] - xa[2];
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(len > 0)) continue;
    if (len > limit * s.rest[i]) over.push_back(static_cast<int>(i));
    const double c = s.k[i] - s.k[i] * s.rest[i] / len;  // k (len - rest) / len
    double* fa = f + 4 * s.a[i];
    double* fb = f + 4 * s.b[i];
    fa[0] += c * dx;
    fa[1] += c * dy;
    fa[2] += c * dz;
    fb[0] -= c * dx;
    fb[1] -= c * dy;
    fb[2] -= c * dz;
  }
}

#ifdef VT_X86
// Four springs per round: their four differences transposed into x, y and z lanes, the lengths
// and coefficients four-wide, then each spring's force added to its ends in order. Returns where
// it stopped (a multiple of four); the scalar loop takes the rest.
__attribute__((target("avx2,fma"))) std::size_t addAvx2(const SpringArrays& s, const double* x, double* f,
                                                        double limit, std::vector<int>& over) {
  const std::size_t n = s.size() / 4 * 4;
  const int* A = s.a.data();
  const int* B = s.b.data();
  const __m256d lim = _mm256_set1_pd(limit);
  const __m256d zero = _mm256_setzero_pd();
  for (std::size_t i = 0; i < n; i += 4) {
    __m256d d[4];
    for (int j = 0; j < 4; ++j)
      d[j] = _mm256_sub_pd(_mm256_load_pd(x + 4 * B[i + j]), _mm256_load_pd(x + 4 * A[i + j]));
    const __m256d t0 = _mm256_unpacklo_pd(d[0], d[1]);  // x0 x1 z0 z1
    const __m256d t1 = _mm256_unpackhi_pd(d[0], d[1]);  // y0 y1 p0 p1
    const __m256d t2 = _mm256_unpacklo_pd(d[2], d[3]);  // x2 x3 z2 z3
    const __m256d t3 = _mm256_unpackhi_pd(d[2], d[3]);  // y2 y3 p2 p3
    const __m256d dx = _mm256_permute2f128_pd(t0, t2, 0x20);
    const __m256d dz = _mm256_permute2f128_pd(t0, t2, 0x31);
    const __m256d dy = _mm256_permute2f128_pd(t1, t3, 0x20);
    const __m256d len = _mm256_sqrt_pd(_mm256_fmadd_pd(dx, dx, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dz, dz))));
    const __m256d rest = _mm256_loadu_pd(s.rest.data() + i);
    const __m256d k = _mm256_loadu_pd(s.k.data() + i);
    const __m256d live = _mm256_cmp_pd(len, zero, _CMP_GT_OQ);  // false for 0 and NaN
    const __m256d c = _mm256_sub_pd(k, _mm256_div_pd(_mm256_mul_pd(k, rest), len));
    const int alive = _mm256_movemask_pd(live);
    int stretched = _mm256_movemask_pd(_mm256_and_pd(live, _mm256_cmp_pd(len, _mm256_mul_pd(lim, rest), _CMP_GT_OQ)));
    while (stretched) {
      over.push_back(static_cast<int>(i) + __builtin_ctz(static_cast<unsigned>(stretched)));
      stretched &= stretched - 1;
    }
    alignas(32) double cs[4];
    _mm256_store_pd(cs, c);
    for (int j = 0; j < 4; ++j) {
      if (!(alive >> j & 1)) continue;  // zero or non-finite length: adds nothing, as in the scalar loop
      const __m256d fj = _mm256_mul_pd(_mm256_set1_pd(cs[j]), d[j]);
      double* fa = f + 4 * A[i + j];
      double* fb = f + 4 * B[i + j];
      _mm256_store_pd(fa, _mm256_add_pd(_mm256_load_pd(fa), fj));
      _mm256_store_pd(fb, _mm256_sub_pd(_mm256_load_pd(fb), fj));
    }
  }
  return n;
}
#endif

}  // namespace

bool vectorSpringKernelAvailable() {
#ifdef VT_X86
  static const bool available = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return available;
#else
  return false;
#endif
}

void addSpringForces(const SpringArrays& springs, const PaddedRows& x, PaddedRows& f, double limit,
                     bool vectorized, std::vector<int>& over) {
  std::size_t done = 0;
#ifdef VT_X86
  if (vectorized && vectorSpringKernelAvailable()) done = addAvx2(springs, x.data(), f.data(), limit, over);
#else
  (void)vectorized;
#endif
  addScalar(springs, done, springs.size(), x.data(), f.data(), limit, over);
}

}  // namespace virtual_tryon
