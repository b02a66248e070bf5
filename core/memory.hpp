// The memory a run may use: the machine's, the budget the stages that could outgrow it check against before
// they start (the deposit's voxels, the part mesh), and the cost each stage declares, so a run too large
// stops with a message and a suggestion rather than being ended by the kernel's out-of-memory killer.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace beadtwin {

// The machine's physical memory in bytes (8 GB when the system does not say).
double physical_memory_bytes();

// The budget: `asked_bytes` when positive (the scenario's output.memory_budget), else three quarters of the
// machine's memory, leaving room for the system and the rest of the run.
double memory_budget_bytes(double asked_bytes = 0.0);

// The memory a stage takes at one voxel size, bytes, split by how it goes with the voxel size: what a stage
// holds per voxel goes as the inverse cube of the voxel size, what it holds per voxel face on a surface as
// the inverse square, the rest not at all. Each stage declares its own (next to the code it measures); the
// runner adds them into the run's peak.
struct MemoryCost {
  double fixed_bytes = 0.0;    // independent of the voxel size
  double volume_bytes = 0.0;   // as the inverse cube of the voxel size
  double surface_bytes = 0.0;  // as the inverse square of the voxel size

  double bytes() const { return fixed_bytes + volume_bytes + surface_bytes; }
  // The same at voxels 1/r times as large (r > 0): voxel size s becomes s / r.
  MemoryCost at_voxel_ratio(double r) const;
  // Every part times `factor` (>= 0).
  MemoryCost scaled(double factor) const;
  MemoryCost& operator+=(const MemoryCost& other);
  friend MemoryCost operator+(MemoryCost a, const MemoryCost& b) { return a += b; }
};

// The smallest voxel size, in tenths of a millimetre, above `voxel_mm` at which `bytes_at(size_mm)` fits in
// `budget_bytes` with a tenth of the budget to spare; 0 when no size would: `least_bytes`, what is needed at
// any voxel size, takes that room already. `bytes_at` must not grow as the voxel size does.
double fitting_voxel_mm(double voxel_mm, double budget_bytes, double least_bytes,
                        const std::function<double(double size_mm)>& bytes_at);
// The same for one cost estimated at `voxel_mm`.
double fitting_voxel_mm(const MemoryCost& cost, double voxel_mm, double budget_bytes);

// Bytes as a person reads them: "0.18 GB", "3.4 GB".
std::string gigabytes(double bytes);

// Asks the kernel to back the whole 2 MiB pages inside [data, data + bytes) with transparent huge pages
// when they are first touched (madvise MADV_HUGEPAGE; nothing where the system has no such pages, or for
// less than one). Each 4 kB page of fresh memory costs a fault when first written, and in a virtual machine
// a fault is dear: filling a few hundred MB of moves page by page can take longer than reading the program
// they came from. Advice only: the memory and its contents are the same either way.
void advise_huge_pages(const void* data, std::size_t bytes);

// `v` with room for `n` elements, that room advised as above before anything is written to it.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace beadtwin
