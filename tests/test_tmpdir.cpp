// Every test binary keeps its temporary files under its own build tree: TMPDIR, which
// std::filesystem::temp_directory_path() and the programs the tests start read, is set before any test runs.
// The tests write to fixed names there, so two build trees testing at once (a fresh clone's CI beside a
// working tree) would otherwise write over each other's files in /tmp.
#include <cstdlib>
#include <filesystem>

namespace {

const bool kTmpdirSet = [] {
  std::filesystem::create_directories(BEADTWIN_TEST_TMPDIR);
  return setenv("TMPDIR", BEADTWIN_TEST_TMPDIR, 1) == 0;
}();

}  // namespace
