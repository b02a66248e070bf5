#include "core/memory.hpp"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace beadtwin {
namespace {

TEST(MemoryBudget, AskedOrThreeQuartersOfTheMachine) {
  EXPECT_DOUBLE_EQ(memory_budget_bytes(5e9), 5e9);
  EXPECT_DOUBLE_EQ(memory_budget_bytes(), 0.75 * physical_memory_bytes());
  EXPECT_GT(physical_memory_bytes(), 0.0);
}

// Voxels r times smaller: r³ times as many, r² times as many faces on a surface, the rest the same.
TEST(MemoryCost, ScalesWithTheVoxelSizeByPart) {
  const MemoryCost c{.fixed_bytes = 100.0, .volume_bytes = 10.0, .surface_bytes = 1.0};
  EXPECT_DOUBLE_EQ(c.bytes(), 111.0);
  const MemoryCost half = c.at_voxel_ratio(2.0);  // voxels half as large
  EXPECT_DOUBLE_EQ(half.fixed_bytes, 100.0);
  EXPECT_DOUBLE_EQ(half.volume_bytes, 80.0);
  EXPECT_DOUBLE_EQ(half.surface_bytes, 4.0);
  const MemoryCost twice = c.at_voxel_ratio(0.5);
  EXPECT_DOUBLE_EQ(twice.volume_bytes, 1.25);
  EXPECT_DOUBLE_EQ(twice.surface_bytes, 0.25);
  EXPECT_DOUBLE_EQ(twice.at_voxel_ratio(2.0).bytes(), c.bytes());
  const MemoryCost tripled = c.scaled(3.0);
  EXPECT_DOUBLE_EQ(tripled.fixed_bytes, 300.0);
  EXPECT_DOUBLE_EQ(tripled.volume_bytes, 30.0);
  EXPECT_DOUBLE_EQ(tripled.surface_bytes, 3.0);
}

TEST(MemoryCost, AddsPartByPart) {
  const MemoryCost a{.fixed_bytes = 1.0, .volume_bytes = 2.0, .surface_bytes = 3.0};
  const MemoryCost b{.fixed_bytes = 10.0, .volume_bytes = 20.0};
  const MemoryCost sum = a + b;
  EXPECT_DOUBLE_EQ(sum.fixed_bytes, 11.0);
  EXPECT_DOUBLE_EQ(sum.volume_bytes, 22.0);
  EXPECT_DOUBLE_EQ(sum.surface_bytes, 3.0);
  MemoryCost c = a;
  c += b;
  EXPECT_DOUBLE_EQ(c.bytes(), a.bytes() + b.bytes());
  // Added then scaled to other voxels, as scaled then added.
  EXPECT_DOUBLE_EQ(sum.at_voxel_ratio(3.0).bytes(),
                   a.at_voxel_ratio(3.0).bytes() + b.at_voxel_ratio(3.0).bytes());
}

// The first tenth of a millimetre above `voxel_mm` at which `bytes_at` fits a tenth below the budget, found
// one tenth at a time.
double fitting_by_steps(double voxel_mm, double budget, const std::function<double(double)>& bytes_at) {
  for (double tenths = std::floor(voxel_mm * 10.0 + 1e-9) + 1.0;; tenths += 1.0)
    if (bytes_at(tenths / 10.0) <= budget / 1.1) return tenths / 10.0;
}

TEST(FittingVoxel, TheSmallestTenthOfAMillimetreThatFitsWithATenthToSpare) {
  // Volume alone: the size where the cost falls to the budget less a tenth, rounded up to a tenth.
  const MemoryCost volume{.volume_bytes = 8e9};  // at 0.5 mm
  const double size = fitting_voxel_mm(volume, 0.5, 1e9);
  EXPECT_DOUBLE_EQ(size, std::ceil(0.5 * std::cbrt(8.0 * 1.1) * 10.0) / 10.0);
  EXPECT_LE(volume.at_voxel_ratio(0.5 / size).bytes(), 1e9 / 1.1);
  EXPECT_GT(volume.at_voxel_ratio(0.5 / (size - 0.1)).bytes(), 1e9 / 1.1);
  // Above the voxel size even when that fits already.
  EXPECT_DOUBLE_EQ(fitting_voxel_mm(volume, 0.5, 1e12), 0.6);
  EXPECT_DOUBLE_EQ(fitting_voxel_mm(volume, 0.55, 1e12), 0.6);
  // What no voxel size changes takes the budget with its tenth to spare: none fits.
  EXPECT_EQ(fitting_voxel_mm({.fixed_bytes = 2e9, .volume_bytes = 1.0}, 0.5, 1.1e9), 0.0);
  EXPECT_GT(fitting_voxel_mm({.fixed_bytes = 0.9e9, .volume_bytes = 1.0}, 0.5, 1.1e9), 0.5);
  // Every mix of parts, over a wide range of sizes: the same tenth as stepping one at a time.
  for (const double fixed : {0.0, 3e8, 8e8})
    for (const double vol : {1e6, 5e9, 2e12})
      for (const double surf : {0.0, 4e8, 9e10})
        for (const double voxel : {0.1, 0.25, 2.54}) {
          const MemoryCost c{.fixed_bytes = fixed, .volume_bytes = vol, .surface_bytes = surf};
          const auto at = [&](double s) { return c.at_voxel_ratio(voxel / s).bytes(); };
          EXPECT_DOUBLE_EQ(fitting_voxel_mm(c, voxel, 1e9), fitting_by_steps(voxel, 1e9, at))
              << fixed << " " << vol << " " << surf << " " << voxel;
        }
  // Any measure that does not grow with the voxel size, with what it needs at any size given apart.
  const auto peak = [](double s) { return 2e8 + std::max(5e9 / (s * s * s), 1e9 / (s * s)); };
  EXPECT_DOUBLE_EQ(fitting_voxel_mm(0.3, 1e9, 2e8, peak), fitting_by_steps(0.3, 1e9, peak));
}

TEST(Gigabytes, TwoDecimalsBelowTenOneAbove) {
  EXPECT_EQ(gigabytes(0.18e9), "0.18 GB");
  EXPECT_EQ(gigabytes(3.4e9), "3.40 GB");
  EXPECT_EQ(gigabytes(53393.04e9), "53393.0 GB");
}

// The mapping of /proc/self/smaps that holds `p`: its text, empty when none does.
std::string smaps_entry(const void* p) {
  const auto at = reinterpret_cast<std::uintptr_t>(p);
  std::ifstream in("/proc/self/smaps");
  std::string line, entry;
  bool inside = false;
  while (std::getline(in, line)) {
    std::uintptr_t from = 0, to = 0;
    char dash = 0;
    std::istringstream head(line);
    // A mapping's first line starts with its address range, "7f12a000-7f12c000 rw-p ...".
    if (head >> std::hex >> from >> dash >> to && dash == '-') {
      if (inside) return entry;
      inside = from <= at && at < to;
      entry.clear();
    }
    if (inside) entry += line + "\n";
  }
  return inside ? entry : std::string();
}

std::string thp_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string text;
  std::getline(in, text);
  return text;
}

TEST(HugePages, ReservedRoomHoldsWhatIsWrittenAndIsAdvised) {
  std::vector<double> v;
  const std::size_t n = std::size_t{3} << 20;  // 24 MB: several whole 2 MiB pages
  reserve_huge(v, n);
  ASSERT_GE(v.capacity(), n);
  const double* room = v.data();
  for (std::size_t i = 0; i < n; ++i) v.push_back(0.5 * static_cast<double>(i));
  EXPECT_EQ(v.data(), room);  // no reallocation: the room was there
  for (std::size_t i = 0; i < n; i += 4099) EXPECT_EQ(v[i], 0.5 * static_cast<double>(i));

  const std::string mode = thp_mode();
  if (mode.find("[never]") != std::string::npos || mode.empty())
    GTEST_SKIP() << "transparent huge pages are off here: nothing to advise";
  // The kernel marks a mapping advised with MADV_HUGEPAGE "hg" in its VmFlags (proc(5)).
  const std::string entry = smaps_entry(v.data() + n / 2);
  ASSERT_FALSE(entry.empty());
  const std::size_t flags = entry.find("VmFlags:");
  ASSERT_NE(flags, std::string::npos);
  EXPECT_NE(entry.find(" hg", flags), std::string::npos) << entry;
}

TEST(HugePages, AdviceOnNothingOrLessThanAPageIsHarmless) {
  advise_huge_pages(nullptr, 0);
  advise_huge_pages(nullptr, std::size_t{64} << 20);
  std::vector<char> small(100, 'x');
  advise_huge_pages(small.data(), small.size());
  advise_huge_pages(small.data() + 1, 7);
  std::vector<int> empty;
  reserve_huge(empty, 0);
  EXPECT_EQ(small[50], 'x');
  EXPECT_TRUE(empty.empty());
}

}  // namespace
}  // namespace beadtwin
