// The memory a run may use: the machine's, and the budget the stages that could outgrow it check against
// before they start (the deposit's voxels, the part mesh), so a run too large stops with a message and a
// suggestion rather than being ended by the kernel's out-of-memory killer.
#pragma once

namespace beadtwin {

// The machine's physical memory in bytes (8 GB when the system does not say).
double physical_memory_bytes();

// The budget: `asked_bytes` when positive (the scenario's output.memory_budget), else three quarters of the
// machine's memory, leaving room for the system and the rest of the run.
double memory_budget_bytes(double asked_bytes = 0.0);

}  // namespace beadtwin
