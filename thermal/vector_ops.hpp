// Blocked, vectorised operations for SUNDIALS' serial N_Vector, internal to the thermal library.
//
// In a step of the part's heat model most of the time goes into CVODE's and GMRES's vector operations over
// every born cell: dot products, weighted norms, linear combinations. The serial vector's own loops add
// their sums one element at a time (a chain of dependent additions the compiler may not reorder), so they
// run at the latency of one addition per element. These replacements split a vector into fixed blocks of
// kBlock elements, reduce each block with Eigen's vectorised kernels (several partial sums at once), run
// the blocks on TBB's threads when the vector is long, and add the block results in block order. A result
// therefore depends on the vector's length only, never on the number of threads or on how TBB schedules
// the blocks: a run's results do not depend on its thread count.
//
// The operations are installed in a vector's table of operations; the clones CVODE and GMRES make of it
// copy the table, so installing them on the vector an integrator is created with is enough. An MPI-parallel
// vector takes the same kernels for its rank's part; its global reductions add the ranks' blocked sums with
// the vector's own all-reduce (its own reductions add one element at a time).
#pragma once

#include <cstddef>

#include <sundials/sundials_nvector.h>

namespace beadtwin::thermal {

// Elements per block: the unit of work of a thread, and the fixed grouping of every sum.
inline constexpr std::size_t kVectorBlock = 4096;

// Replaces the hot operations of vector `v`: serial (N_VNew_Serial), or with `parallel` MPI-parallel
// (N_VNew_Parallel), with fused operations enabled.
void use_blocked_vector_ops(N_Vector v, bool parallel = false);

}  // namespace beadtwin::thermal
