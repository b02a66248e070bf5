// The whole of a file as the tests read it back (reports, exported files), bytes as they are.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace beadtwin::testing {

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace beadtwin::testing
