#include "core/memory.hpp"

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
