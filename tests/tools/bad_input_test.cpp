// The bad-input corpus (tests/bad/cases.yaml): every case ends with its exit code and its message, within a
// time limit, never with an internal error, and a case that stops with exit code 2 leaves no file behind.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "tests/shell.hpp"

namespace {

namespace fs = std::filesystem;

// Runs `args` from tests/bad with a time limit: an endless loop is a failure, not a hang.
beadtwin::testing::ShellResult run_case(const std::string& args) {
  return beadtwin::testing::shell("cd " + (fs::path(BEADTWIN_SOURCE_DIR) / "tests/bad").string() +
                                  " && timeout 120 " + BEADTWIN_BINARY + " " + args + " 2>&1");
}

TEST(BadInput, EveryCaseEndsWithItsExitCodeAndMessage) {
  const YAML::Node cases = YAML::LoadFile(std::string(BEADTWIN_SOURCE_DIR) + "/tests/bad/cases.yaml");
  ASSERT_GE(cases.size(), 15u);
  // docs/RELIABILITY.md's table lists every case.
  std::ifstream doc_file(std::string(BEADTWIN_SOURCE_DIR) + "/docs/RELIABILITY.md");
  const std::string doc((std::istreambuf_iterator<char>(doc_file)), {});
  int n = 0;
  for (const YAML::Node& c : cases) {
    const std::string name = c["case"].as<std::string>();
    SCOPED_TRACE(name);
    EXPECT_NE(doc.find("| " + name + " | `beadtwin " + c["run"].as<std::string>() + "` | " +
                       std::to_string(c["exit"].as<int>()) + " |"),
              std::string::npos)
        << "docs/RELIABILITY.md has no row for this case";
    const fs::path out = fs::temp_directory_path() / ("bt_bad_" + std::to_string(n++));
    fs::remove_all(out);
    // An input made for the case in {out}: a file of `bytes` comment characters, or a named pipe.
    std::string made;
    if (const YAML::Node make = c["make"]) {
      fs::create_directories(out);
      if (make["fifo"]) {
        made = make["fifo"].as<std::string>();
        ASSERT_EQ(::mkfifo((out / made).c_str(), 0600), 0);
      } else {
        made = make["file"].as<std::string>();
        std::ofstream(out / made, std::ios::binary) << std::string(make["bytes"].as<std::size_t>(), '#');
      }
    }
    std::string args = c["run"].as<std::string>();
    for (std::size_t at; (at = args.find("{out}")) != std::string::npos;) args.replace(at, 5, out.string());
    const beadtwin::testing::ShellResult r = run_case(args);
    EXPECT_EQ(r.code, c["exit"].as<int>()) << r.output;
    EXPECT_NE(r.output.find(c["message"].as<std::string>()), std::string::npos) << r.output;
    // Exit 3 is an internal error: no input may cause one.
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    // Stopped: nothing written (a run stages its files and moves them into place only when complete), and
    // nothing half-written or staged left behind.
    if (r.code == 2 && fs::exists(out)) {
      for (const auto& e : fs::recursive_directory_iterator(out)) {
        if (e.path().filename() == made || e.is_directory()) continue;
        ADD_FAILURE() << "stopped with exit code 2 but wrote " << e.path();
      }
    }
  }
}

}  // namespace
