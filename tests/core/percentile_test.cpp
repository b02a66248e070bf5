// Weighted percentiles by selection against the definition: sort by value, walk, stop where the summed
// weight reaches the fraction of the total.
#include "core/percentile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace beadtwin {
namespace {

double by_sorting(std::vector<Weighted> items, double total, double fraction) {
  std::stable_sort(items.begin(), items.end(),
                   [](const Weighted& a, const Weighted& b) { return a.value < b.value; });
  double seen = 0.0;
  for (const Weighted& w : items) {
    seen += w.weight;
    if (seen >= fraction * total) return w.value;
  }
  return items.back().value;
}

TEST(WeightedPercentile, NamesTheValueASortedWalkNames) {
  std::mt19937 random(7);
  // Sizes below, at and well above the part that is sorted; values with many ties (a few dozen levels) and
  // without; weights whose sums are exact in binary (multiples of 1/8), so the walk's order cannot matter.
  for (const std::size_t n : {1u, 5u, 64u, 65u, 1000u, 100000u}) {
    for (const int levels : {20, 1 << 30}) {
      std::uniform_int_distribution<int> value(0, levels), eighths(1, 40);
      std::vector<Weighted> items(n);
      double total = 0.0;
      for (Weighted& w : items) {
        w = {static_cast<double>(value(random)) * 0.01, eighths(random) / 8.0};
        total += w.weight;
      }
      for (const double fraction : {0.0, 0.05, 0.25, 0.5, 0.95, 1.0}) {
        std::vector<Weighted> copy = items;
        EXPECT_EQ(weighted_percentile(copy, total, fraction), by_sorting(items, total, fraction))
            << n << " items, " << levels << " levels, fraction " << fraction;
      }
    }
  }
}

TEST(WeightedPercentile, AFractionOnAnItemsEdgeNamesThatItem) {
  // 4,096 items of weight 1 and distinct values: the fraction k / 4096 reaches the summed weight exactly at
  // the k-th item by value, which is the percentile (reached counts); every k, so that the search also ends
  // at the middle item of the ranges it splits.
  std::mt19937 random(11);
  std::vector<Weighted> items(4096);
  for (std::size_t i = 0; i < items.size(); ++i) items[i] = {static_cast<double>(i) * 0.5, 1.0};
  std::shuffle(items.begin(), items.end(), random);
  const auto n = static_cast<double>(items.size());
  for (std::size_t k = 1; k <= items.size(); ++k) {
    std::vector<Weighted> copy = items;
    ASSERT_EQ(weighted_percentile(copy, n, static_cast<double>(k) / n), static_cast<double>(k - 1) * 0.5)
        << k;
  }
}

TEST(WeightedPercentile, HeavyItemsCarryTheirWeight) {
  // By value: 1 (weight 0.5), 2 (18), 3 (1), 4 (0.5); summed: 0.5, 18.5, 19.5, 20. The heavy item is every
  // percentile from 2.5 % to 92.5 %.
  std::vector<Weighted> items = {{3.0, 1.0}, {1.0, 0.5}, {2.0, 18.0}, {4.0, 0.5}};
  EXPECT_EQ(weighted_percentile(items, 20.0, 0.0), 1.0);
  EXPECT_EQ(weighted_percentile(items, 20.0, 0.025), 1.0);
  EXPECT_EQ(weighted_percentile(items, 20.0, 0.03), 2.0);
  EXPECT_EQ(weighted_percentile(items, 20.0, 0.5), 2.0);
  EXPECT_EQ(weighted_percentile(items, 20.0, 0.925), 2.0);
  EXPECT_EQ(weighted_percentile(items, 20.0, 0.95), 3.0);
  EXPECT_EQ(weighted_percentile(items, 20.0, 1.0), 4.0);
}

}  // namespace
}  // namespace beadtwin
