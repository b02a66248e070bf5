#include "core/memory.hpp"

#include <cmath>
#include <cstdint>

#include <fmt/format.h>

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

MemoryCost MemoryCost::at_voxel_ratio(double r) const {
  return {fixed_bytes, volume_bytes * (r * r * r), surface_bytes * (r * r)};
}

MemoryCost MemoryCost::scaled(double factor) const {
  return {fixed_bytes * factor, volume_bytes * factor, surface_bytes * factor};
}

MemoryCost& MemoryCost::operator+=(const MemoryCost& other) {
  fixed_bytes += other.fixed_bytes;
  volume_bytes += other.volume_bytes;
  surface_bytes += other.surface_bytes;
  return *this;
}

double fitting_voxel_mm(double voxel_mm, double budget_bytes, double least_bytes,
                        const std::function<double(double size_mm)>& bytes_at) {
  const double room = budget_bytes / 1.1;  // a tenth to spare
  if (!(least_bytes < room)) return 0.0;   // no voxel size would do
  // The first tenth of a millimetre above the voxel size at which the bytes fit: they do before the voxels
  // are as large as the room left over makes what goes with them. The bytes never grow with the size, so
  // doubling steps find a size that fits and halving steps the first one.
  const double first = std::floor(voxel_mm * 10.0 + 1e-9) + 1.0;
  const auto fits = [&](double tenths) { return bytes_at(tenths / 10.0) <= room; };
  double step = 1.0;
  while (!fits(first + step - 1.0)) step *= 2.0;
  if (step == 1.0) return first / 10.0;
  double below = first + step / 2.0 - 1.0, at = first + step - 1.0;  // `below` does not fit, `at` does
  while (at - below > 1.0) {
    const double mid = std::floor(0.5 * (below + at));
    (fits(mid) ? at : below) = mid;
  }
  return at / 10.0;
}

double fitting_voxel_mm(const MemoryCost& cost, double voxel_mm, double budget_bytes) {
  return fitting_voxel_mm(voxel_mm, budget_bytes, cost.fixed_bytes,
                          [&](double size_mm) { return cost.at_voxel_ratio(voxel_mm / size_mm).bytes(); });
}

std::string gigabytes(double bytes) {
  return bytes < 10e9 ? fmt::format("{:.2f} GB", bytes / 1e9) : fmt::format("{:.1f} GB", bytes / 1e9);
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
