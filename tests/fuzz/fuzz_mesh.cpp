// libFuzzer target: the mesh reader (read_mesh: our STL header check, assimp's importers, our PLY reader,
// then our repair: welding, duplicate and degenerate faces, winding, shells, cavities). Any bytes give a mesh
// or an InputError, nothing else.
//
// read_mesh reads a file, as a run does, and picks the importer by the file's extension. The bytes are
// written as part.ply when they start with "ply", part.obj when a line starts with "v " or "f ", part.stl
// otherwise (binary or ASCII), in a directory of this process's own under the temporary directory, removed
// at exit.
#include <unistd.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "slicer/mesh.hpp"

using namespace beadtwin;

namespace {

// This process's folder for the file read, removed at exit.
const std::filesystem::path& work_dir() {
  static const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("beadtwin-fuzz-mesh-" + std::to_string(getpid()));
  return dir;
}

const std::filesystem::path& file_for(int format) {
  static const std::array<std::filesystem::path, 3> files = [] {
    std::filesystem::create_directories(work_dir());
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(work_dir(), ec);
    });
    return std::array{work_dir() / "part.stl", work_dir() / "part.obj", work_dir() / "part.ply"};
  }();
  return files[format];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const bool obj = bytes.starts_with("v ") || bytes.starts_with("f ") ||
                   bytes.find("\nv ") != std::string_view::npos ||
                   bytes.find("\nf ") != std::string_view::npos;
  const std::filesystem::path& path = file_for(bytes.starts_with("ply") ? 2 : obj ? 1 : 0);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  try {
    slicer::MeshReport report;
    slicer::read_mesh(path, 1.0, &report);
  } catch (const InputError&) {
  }
  return 0;
}
