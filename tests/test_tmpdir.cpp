// Every test keeps its temporary files in a folder of its own under its build tree: TMPDIR, which
// std::filesystem::temp_directory_path() and the programs the tests start read, is set to
// <build>/tests/tmp/<Suite.Test> as each test starts. The tests write to fixed names there, and ctest runs
// them two at a time, each in its own process: a shared folder let one test rewrite a scenario file while
// another was reading it. A folder per build tree also keeps a fresh clone's CI apart from a working tree.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace {

void use_tmpdir(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  setenv("TMPDIR", dir.c_str(), 1);
}

class TmpdirPerTest : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo& test) override {
    std::string name = std::string(test.test_suite_name()) + "." + test.name();
    for (char& c : name)  // value-parameterised names carry '/'
      if (c == '/') c = '_';
    use_tmpdir(std::filesystem::path(BEADTWIN_TEST_TMPDIR) / name);
  }
};

const bool kTmpdirSet = [] {
  use_tmpdir(BEADTWIN_TEST_TMPDIR);  // for what runs before the first test starts
  ::testing::UnitTest::GetInstance()->listeners().Append(new TmpdirPerTest);
  return true;
}();

}  // namespace
