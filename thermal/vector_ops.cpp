#include "thermal/vector_ops.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Core>

namespace beadtwin::thermal {
namespace {

using ConstMap = Eigen::Map<const Eigen::ArrayXd>;
using Map = Eigen::Map<Eigen::ArrayXd>;

// Vectors of fewer blocks than this run on the calling thread: below it, handing blocks to other threads
// costs more than it saves.
constexpr std::size_t kParallelBlocks = 64;

// This rank's part of the vector (all of a serial one; the serial vector has no local-length operation).
std::size_t length(N_Vector v) {
  return static_cast<std::size_t>(v->ops->nvgetlocallength != nullptr ? v->ops->nvgetlocallength(v)
                                                                      : N_VGetLength(v));
}
double* data(N_Vector v) {
  return N_VGetArrayPointer(v);
}

std::size_t block_count(std::size_t n) {
  return (n + kVectorBlock - 1) / kVectorBlock;
}

// Calls f(begin, end) for each block of [0, n), on TBB's threads when there are enough blocks.
template <class F>
void for_blocks(std::size_t n, const F& f) {
  const std::size_t blocks = block_count(n);
  const auto one = [&](std::size_t b) { f(b * kVectorBlock, std::min(n, (b + 1) * kVectorBlock)); };
  if (blocks < kParallelBlocks) {
    for (std::size_t b = 0; b < blocks; ++b) one(b);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t b = r.begin(); b != r.end(); ++b) one(b);
                    });
}

// `sums` reductions over [0, n): f(begin, end, out) writes the `sums` partial sums of a block to out; the
// totals, added block by block in order, go to `total`.
template <class F>
void reduce_blocks(std::size_t n, std::size_t sums, const F& f, double* total) {
  const std::size_t blocks = block_count(n);
  thread_local std::vector<double> partial;
  partial.assign(blocks * sums, 0.0);
  double* p = partial.data();
  for_blocks(n, [&](std::size_t b, std::size_t e) { f(b, e, p + (b / kVectorBlock) * sums); });
  std::fill(total, total + sums, 0.0);
  for (std::size_t k = 0; k < blocks; ++k)
    for (std::size_t j = 0; j < sums; ++j) total[j] += p[k * sums + j];
}

ConstMap view(N_Vector v, std::size_t b, std::size_t e) {
  return ConstMap(data(v) + b, static_cast<Eigen::Index>(e - b));
}
Map view_out(N_Vector v, std::size_t b, std::size_t e) {
  return Map(data(v) + b, static_cast<Eigen::Index>(e - b));
}

void linear_sum(double a, N_Vector x, double c, N_Vector y, N_Vector z) {
  for_blocks(length(z), [&](std::size_t b, std::size_t e) {
    view_out(z, b, e) = a * view(x, b, e) + c * view(y, b, e);
  });
}

void constant(double c, N_Vector z) {
  for_blocks(length(z), [&](std::size_t b, std::size_t e) { view_out(z, b, e) = c; });
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  for_blocks(length(z),
             [&](std::size_t b, std::size_t e) { view_out(z, b, e) = view(x, b, e) * view(y, b, e); });
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  for_blocks(length(z),
             [&](std::size_t b, std::size_t e) { view_out(z, b, e) = view(x, b, e) / view(y, b, e); });
}

void scale(double c, N_Vector x, N_Vector z) {
  for_blocks(length(z), [&](std::size_t b, std::size_t e) { view_out(z, b, e) = c * view(x, b, e); });
}

double dot(N_Vector x, N_Vector y) {
  double total = 0.0;
  reduce_blocks(
      length(x), 1,
      [&](std::size_t b, std::size_t e, double* out) { *out = (view(x, b, e) * view(y, b, e)).sum(); },
      &total);
  return total;
}

double weighted_square_sum(N_Vector x, N_Vector w) {
  double total = 0.0;
  reduce_blocks(
      length(x), 1,
      [&](std::size_t b, std::size_t e, double* out) {
        *out = (view(x, b, e) * view(w, b, e)).square().sum();
      },
      &total);
  return total;
}

double weighted_rms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<double>(length(x)));
}

// z = Σ c_j X_j. z may be X_0 (as with the serial vector's own, not another of the X_j).
int linear_combination(int count, double* c, N_Vector* xs, N_Vector z) {
  const auto m = static_cast<std::size_t>(count);
  for_blocks(length(z), [&](std::size_t b, std::size_t e) {
    Map out = view_out(z, b, e);
    out = c[0] * view(xs[0], b, e);
    for (std::size_t j = 1; j < m; ++j) out += c[j] * view(xs[j], b, e);
  });
  return 0;
}

// Z_j = a_j x + Y_j.
int scale_add_multi(int count, double* a, N_Vector x, N_Vector* ys, N_Vector* zs) {
  const auto m = static_cast<std::size_t>(count);
  for_blocks(length(x), [&](std::size_t b, std::size_t e) {
    for (std::size_t j = 0; j < m; ++j) view_out(zs[j], b, e) = a[j] * view(x, b, e) + view(ys[j], b, e);
  });
  return 0;
}

// d_j = x · Y_j, all in one pass over x's blocks.
int dot_multi(int count, N_Vector x, N_Vector* ys, double* d) {
  const auto m = static_cast<std::size_t>(count);
  reduce_blocks(
      length(x), m,
      [&](std::size_t b, std::size_t e, double* out) {
        const ConstMap xb = view(x, b, e);
        for (std::size_t j = 0; j < m; ++j) out[j] = (xb * view(ys[j], b, e)).sum();
      },
      d);
  return 0;
}

// The global reductions of an MPI-parallel vector: this rank's blocked sums, then the sum over the ranks by
// the vector's own all-reduce (MPI_Allreduce, in place).
void sum_over_ranks(N_Vector x, int count, double* values) {
  if (x->ops->nvdotprodmultiallreduce(count, x, values) != 0)
    *values = std::numeric_limits<double>::quiet_NaN();
}

double dot_over_ranks(N_Vector x, N_Vector y) {
  double d = dot(x, y);
  sum_over_ranks(x, 1, &d);
  return d;
}

double weighted_rms_norm_over_ranks(N_Vector x, N_Vector w) {
  double s = weighted_square_sum(x, w);
  sum_over_ranks(x, 1, &s);
  return std::sqrt(s / static_cast<double>(N_VGetLength(x)));  // the global length
}

int dot_multi_over_ranks(int count, N_Vector x, N_Vector* ys, double* d) {
  dot_multi(count, x, ys, d);
  return x->ops->nvdotprodmultiallreduce(count, x, d);
}

}  // namespace

void use_blocked_vector_ops(N_Vector v, bool parallel) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = &linear_sum;
  ops->nvconst = &constant;
  ops->nvprod = &product;
  ops->nvdiv = &quotient;
  ops->nvscale = &scale;
  ops->nvdotprodlocal = &dot;
  ops->nvwsqrsumlocal = &weighted_square_sum;
  ops->nvlinearcombination = &linear_combination;
  ops->nvscaleaddmulti = &scale_add_multi;
  ops->nvdotprodmultilocal = &dot_multi;
  if (parallel) {
    // Without the vector's all-reduce (N_VEnableDotProdMultiLocal_Parallel) its own reductions stay.
    if (ops->nvdotprodmultiallreduce == nullptr) return;
    ops->nvdotprod = &dot_over_ranks;
    ops->nvwrmsnorm = &weighted_rms_norm_over_ranks;
    ops->nvdotprodmulti = &dot_multi_over_ranks;
    return;
  }
  ops->nvdotprod = &dot;
  ops->nvwrmsnorm = &weighted_rms_norm;
  ops->nvdotprodmulti = &dot_multi;
}

}  // namespace beadtwin::thermal
