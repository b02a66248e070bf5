// Weighted percentiles by selection.
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

namespace beadtwin {

// The median of `values` (not empty): the middle item, the upper of the two middle ones for an even count.
inline double median(std::vector<double> values) {
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// A value and the weight it stands for (a sample's stock and its area, say).
struct Weighted {
  double value = 0.0;
  double weight = 0.0;
};

// The weighted percentile: the value of the item at which the weight, summed in order of value, first
// reaches `fraction` of `total_weight` (the sum of all the weights); the largest value when rounding keeps
// the sum short of it (a fraction of 1). Found by selection, not by sorting every item: the range that holds
// it is split around its middle item (std::nth_element), the weight of the lower part tells which side it
// lies on, and the search goes on there (or ends at the middle item) until a few dozen items are left to
// sort and walk: O(n) on average. The sums run in another order than a sort's walk, so where the fraction
// falls within a rounding of an item's edge the two may name neighbouring values. Reorders `items`, which
// must not be empty; deterministic for a given order of `items`.
inline double weighted_percentile(std::vector<Weighted>& items, double total_weight, double fraction) {
  constexpr std::size_t kSorted = 64;
  const auto by_value = [](const Weighted& a, const Weighted& b) { return a.value < b.value; };
  const double target = fraction * total_weight;
  const auto at = [&](std::size_t i) { return items.begin() + static_cast<std::ptrdiff_t>(i); };
  std::size_t lo = 0, hi = items.size();
  double before = 0.0;  // the weight of the items below [lo, hi) in order of value
  while (hi - lo > kSorted) {
    const std::size_t mid = lo + (hi - lo) / 2;
    std::nth_element(at(lo), at(mid), at(hi), by_value);
    double lower = 0.0;
    for (std::size_t i = lo; i < mid; ++i) lower += items[i].weight;
    if (before + lower >= target) {
      hi = mid;
      continue;
    }
    before += lower + items[mid].weight;
    if (before >= target) return items[mid].value;
    lo = mid + 1;
  }
  std::sort(at(lo), at(hi), by_value);
  for (std::size_t i = lo; i < hi; ++i) {
    before += items[i].weight;
    if (before >= target) return items[i].value;
  }
  return std::max_element(items.begin(), items.end(), by_value)->value;
}

}  // namespace beadtwin
