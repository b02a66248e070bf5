#include "render/sampling.hpp"

#include <set>
#include <vector>

#include <gtest/gtest.h>

namespace beadtwin::render {
namespace {

TEST(Sampling, PermuteIsABijection) {
  for (const std::uint32_t count : {1u, 2u, 3u, 7u, 16u, 17u, 100u})
    for (const std::uint32_t seed : {0u, 1u, 0xdeadbeefu}) {
      std::set<std::uint32_t> seen;
      for (std::uint32_t i = 0; i < count; ++i) {
        const std::uint32_t p = permute(i, count, seed);
        EXPECT_LT(p, count);
        seen.insert(p);
      }
      EXPECT_EQ(seen.size(), count) << "count " << count << " seed " << seed;
    }
}

TEST(Sampling, SamplesAreStratifiedInBothAxes) {
  for (const std::uint32_t n : {1u, 2u, 3u, 4u, 5u, 8u, 9u, 16u, 64u})
    for (const std::uint32_t seed : {1u, 42u, pixel_seed(7, 9)}) {
      std::set<int> rows, columns;
      for (std::uint32_t s = 0; s < n; ++s) {
        const Eigen::Vector2f p = cmj_sample(s, n, seed);
        ASSERT_GE(p.x(), 0.0f);
        ASSERT_LT(p.x(), 1.0f);
        ASSERT_GE(p.y(), 0.0f);
        ASSERT_LT(p.y(), 1.0f);
        rows.insert(static_cast<int>(p.y() * static_cast<float>(n)));
        columns.insert(static_cast<int>(p.x() * static_cast<float>(n)));
      }
      EXPECT_EQ(rows.size(), n) << "n " << n;
      const auto m = static_cast<std::uint32_t>(std::sqrt(n));
      if (m * m == n) {
        EXPECT_EQ(columns.size(), n) << "n " << n;  // N-rooks in x too when n is square
      }
    }
}

TEST(Sampling, PatternsAreDeterministicAndDifferBetweenPixels) {
  EXPECT_EQ(cmj_sample(3, 16, 99), cmj_sample(3, 16, 99));
  EXPECT_NE(cmj_sample(3, 16, pixel_seed(0, 0)), cmj_sample(3, 16, pixel_seed(1, 0)));
  EXPECT_NE(pixel_seed(1, 2), pixel_seed(2, 1));
}

}  // namespace
}  // namespace beadtwin::render
