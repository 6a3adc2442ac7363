// The spring-force kernel of the cloth: every spring's force added to its two end nodes, on node
// rows padded to four doubles so that a node is one 256-bit load.
//
//   d = x_b - x_a,  f_a += k (|d| - l0) d / |d|,  f_b -= the same
//
// Two implementations with the same contract: a scalar loop, and an AVX2 + FMA one that takes four
// springs at a time (square roots and divisions four-wide, the scatter one spring after the other
// so that springs sharing a node add in order). The vector one is compiled for that target alone
// and chosen at run time when the processor has AVX2 and FMA, so the library still runs on any
// x86-64 (and builds elsewhere, scalar only). Both add the springs in index order; they differ in
// the last bits (FMA rounds once), never in which springs count as over-stretched at a margin
// wider than that.
#pragma once

#include <cstddef>
#include <vector>

namespace virtual_tryon {

// Springs as parallel arrays (the kernel streams through them).
struct SpringArrays {
  std::vector<int> a, b;
  std::vector<double> rest, k;
  std::size_t size() const { return a.size(); }
};

// n rows of (x, y, z, pad), 32-byte aligned.
class PaddedRows {
 public:
  void resize(std::size_t n) {
    buffer_.assign(4 * n + 4, 0.0);
    const std::size_t misalignment = reinterpret_cast<std::size_t>(buffer_.data()) % 32;
    data_ = buffer_.data() + (misalignment ? (32 - misalignment) / sizeof(double) : 0);
    rows_ = n;
  }
  std::size_t rows() const { return rows_; }
  double* data() { return data_; }
  const double* data() const { return data_; }
  double* row(std::size_t i) { return data_ + 4 * i; }
  const double* row(std::size_t i) const { return data_ + 4 * i; }

 private:
  std::vector<double> buffer_;
  double* data_ = nullptr;
  std::size_t rows_ = 0;
};

// True when this processor runs the AVX2 + FMA kernel.
bool vectorSpringKernelAvailable();

// Adds every spring's force to f (rows of `x` and `f` indexed by node); a spring of zero (or
// non-finite) length adds nothing. Appends to `over`, in increasing order, every spring longer
// than limit * rest. `vectorized`: the AVX2 kernel when available, else the scalar loop.
void addSpringForces(const SpringArrays& springs, const PaddedRows& x, PaddedRows& f, double limit,
                     bool vectorized, std::vector<int>& over);

}  // namespace virtual_tryon
