// The memory a run may use: the machine's, and the budget the stages that could outgrow it check against
// before they start (the deposit's voxels, the part mesh), so a run too large stops with a message and a
// suggestion rather than being ended by the kernel's out-of-memory killer.
#pragma once

#include <cstddef>
#include <vector>

namespace beadtwin {

// The machine's physical memory in bytes (8 GB when the system does not say).
double physical_memory_bytes();

// The budget: `asked_bytes` when positive (the scenario's output.memory_budget), else three quarters of the
// machine's memory, leaving room for the system and the rest of the run.
double memory_budget_bytes(double asked_bytes = 0.0);

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
