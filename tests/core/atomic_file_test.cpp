#include "core/atomic_file.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/read_file.hpp"

namespace beadtwin {
namespace {

namespace fs = std::filesystem;
using testing::read_file;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("bt_atomic_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(StagedDir, CommitMovesEveryFileIntoPlace) {
  const fs::path out = fresh_dir("commit");
  std::ofstream(out / "report.json") << "old report";
  {
    StagedDir staged(out);
    EXPECT_EQ(staged.dir().parent_path(), out);
    EXPECT_TRUE(staged.dir().filename().string().starts_with(".tmp-"));
    fs::create_directories(staged.dir() / "baseline" / "progress");
    write_file_atomic(staged.dir() / "baseline" / "program.nc", "G1 X1\n");
    write_file_atomic(staged.dir() / "baseline" / "progress" / "frame-0000.png", "frame");
    write_file_atomic(staged.dir() / "report.json", "new report");
    EXPECT_EQ(read_file(out / "report.json"), "old report");  // nothing moves before commit
    EXPECT_FALSE(fs::exists(out / "baseline"));
    staged.commit({"report.json", "not-written.md"});
  }
  EXPECT_EQ(read_file(out / "baseline" / "program.nc"), "G1 X1\n");
  EXPECT_EQ(read_file(out / "baseline" / "progress" / "frame-0000.png"), "frame");
  EXPECT_EQ(read_file(out / "report.json"), "new report");
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_FALSE(e.path().filename().string().starts_with(".tmp-")) << e.path();
}

TEST(StagedDir, WithoutCommitNothingArrivesAndNothingStays) {
  const fs::path out = fresh_dir("abandon");
  {
    StagedDir staged(out);
    write_file_atomic(staged.dir() / "report.json", "a run that stopped");
  }
  EXPECT_TRUE(fs::is_empty(out));
}

TEST(StagedDir, AKilledRunsFolderIsSweptByTheNextRun) {
  const fs::path out = fresh_dir("stale");
  // No process has this id: the run that made it is gone.
  fs::create_directories(out / ".tmp-4999999-run" / "baseline");
  std::ofstream(out / ".tmp-4999999-run" / "baseline" / "program.nc") << "half a run";
  // One of this process (still running) is kept.
  const fs::path mine = out / (".tmp-" + std::to_string(::getpid()) + "-run");
  fs::create_directories(mine);
  prepare_output_dir(out, "--out");
  EXPECT_FALSE(fs::exists(out / ".tmp-4999999-run"));
  EXPECT_TRUE(fs::exists(mine));
}

}  // namespace
}  // namespace beadtwin
