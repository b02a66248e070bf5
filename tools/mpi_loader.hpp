// Finding out whether beadtwin was launched by mpirun or srun, and loading the MPI module then
// (tools/mpi_module.hpp says why MPI lives in a module).
#pragma once

#include <vector>

namespace beadtwin::tools {

// Launched by mpirun or srun (their environment), rather than run plainly.
bool launched_by_mpi();

// This process's environment without what mpirun or srun put in it, for a child that must run plainly (a
// sweep's variant, started by a rank). Null-terminated, for posix_spawn; the strings are environ's own.
std::vector<char*> environment_without_mpi();

#ifdef BEADTWIN_MPI_MODULE
// The MPI module's entry `name`: from beside the running program, else from where the build put it. Throws
// InternalError when it cannot be loaded.
void* mpi_module_entry(const char* name);
#endif

}  // namespace beadtwin::tools
