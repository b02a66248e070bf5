// A loop over indices shared out among TBB's threads when it is long enough to be worth it, internal to the
// thermal library (the heat model's right-hand side and Jacobian products, the healing integrator). Each
// index is handled by one call of f, so a loop whose calls write only their own entries gives the same
// result on any number of threads.
#pragma once

#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace beadtwin::thermal {

// f(i) for every i in [begin, end), on TBB's threads when there are enough to be worth handing out.
template <class F>
void for_range(std::size_t begin, std::size_t end, const F& f) {
  constexpr std::size_t kGrain = 4096;
  if (end < begin + 2 * kGrain) {
    for (std::size_t i = begin; i < end; ++i) f(i);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
                    });
}

}  // namespace beadtwin::thermal
