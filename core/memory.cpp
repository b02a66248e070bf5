#include "core/memory.hpp"

#include <cstdint>

#include <sys/mman.h>
#include <unistd.h>

namespace beadtwin {

double physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
}

double memory_budget_bytes(double asked_bytes) {
  return asked_bytes > 0.0 ? asked_bytes : 0.75 * physical_memory_bytes();
}

void advise_huge_pages(const void* data, std::size_t bytes) {
#ifdef MADV_HUGEPAGE
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  const auto from = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (from + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (from + bytes) & ~(kHuge - 1);
  if (data == nullptr || last <= first) return;
  // Failure (no transparent huge pages in this kernel) leaves the memory as it was: nothing to report.
  (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace beadtwin
