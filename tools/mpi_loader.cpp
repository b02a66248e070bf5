#include "tools/mpi_loader.hpp"

#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <dlfcn.h>
#include <fmt/format.h>

#include "core/error.hpp"
#include "tools/mpi_module.hpp"

extern char** environ;

namespace beadtwin::tools {
namespace {

// What Open MPI (OMPI_, PMIX_), Slurm's and MPICH's process managers (PMI_, MPI_LOCAL) put in a rank's
// environment.
bool from_mpi(std::string_view variable) {
  for (const std::string_view prefix : {"OMPI_", "PMIX_", "PMI_", "MPI_LOCAL"})
    if (variable.starts_with(prefix)) return true;
  return false;
}

}  // namespace

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}

std::vector<char*> environment_without_mpi() {
  std::vector<char*> out;
  for (char** e = environ; *e != nullptr; ++e)
    if (!from_mpi(*e)) out.push_back(*e);
  out.push_back(nullptr);
  return out;
}

#ifdef BEADTWIN_MPI_MODULE

void* mpi_module_entry(const char* name) {
  namespace fs = std::filesystem;
  std::vector<fs::path> tried;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) tried.push_back(self.parent_path() / mpi::kModuleName);
  tried.emplace_back(BEADTWIN_MPI_MODULE);
  std::string errors;
  for (const fs::path& path : tried) {
    if (!fs::exists(path, ec)) continue;
    void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module) {
      errors += std::string("; ") + dlerror();
      continue;
    }
    if (void* entry = dlsym(module, name)) return entry;
    errors += "; " + path.string() + " has no " + name;
  }
  std::string where;
  for (const fs::path& path : tried) where += (where.empty() ? "" : ", ") + path.string();
  throw InternalError(
      fmt::format("cannot load the MPI module {} (looked for {}){}", mpi::kModuleName, where, errors));
}

#endif

}  // namespace beadtwin::tools
