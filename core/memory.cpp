#include "core/memory.hpp"

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

}  // namespace beadtwin
