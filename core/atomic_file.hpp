// Files written atomically: content goes to a temporary name beside the target and is renamed
// into place only when complete, so an interrupted run never leaves a half-written output.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace beadtwin {

// Makes `dir` (and its parents) if missing and checks that files can be written in it: before a run, so a
// bad output directory stops it at once rather than after the work. Throws InputError (key `option`, the
// command-line option that named it) saying why, with exit code 2.
void prepare_output_dir(const std::filesystem::path& dir, const std::string& option);

// Writes `content` to `path` atomically. Throws std::runtime_error naming the path on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// For writers that need a file name (image libraries): write to temp(), then commit().
// If commit() is never called the temporary file is removed.
class AtomicPath {
 public:
  explicit AtomicPath(std::filesystem::path target);
  ~AtomicPath();
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;

  // The name to write to: beside the target, with the target's extension last (image writers choose the
  // format from it).
  const std::filesystem::path& temp() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }
  // Renames temp() to target(). Throws std::runtime_error naming both when it cannot.
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path temp_;
  bool committed_ = false;
};

// For writers that stream their content: a binary stream to a temporary file beside the target, renamed
// into place by commit() once everything is written. Errors (the folder missing or not writable, a full
// disk) throw std::runtime_error naming the target; without commit() nothing is left behind.
class AtomicStream {
 public:
  explicit AtomicStream(std::filesystem::path target);

  std::ostream& stream() { return out_; }
  const std::filesystem::path& target() const { return path_.target(); }
  // Flushes, checks that every byte was written, and renames the file into place.
  void commit();

 private:
  AtomicPath path_;
  std::ofstream out_;
};

// A run's outputs, written into a hidden folder inside `target` (.tmp-PID-run) and moved into place together
// by commit(), so that a run stopped part-way (bad input found late, an internal error, Ctrl-C) leaves the
// previous run's files as they were rather than a new program beside an old report. The folder is removed
// when the StagedDir goes (empty after commit(), with what it holds without); one a killed process left is
// removed by the next prepare_output_dir on `target`.
class StagedDir {
 public:
  explicit StagedDir(std::filesystem::path target);
  ~StagedDir();
  StagedDir(const StagedDir&) = delete;
  StagedDir& operator=(const StagedDir&) = delete;

  const std::filesystem::path& dir() const { return stage_; }
  // Moves every staged file to the same place under the target, making folders as needed: first all but
  // those named in `last` (paths relative to the folder), then those in the order given, so the reports
  // arrive after what they describe. Throws std::runtime_error naming a file that cannot be moved.
  void commit(const std::vector<std::string>& last);

 private:
  std::filesystem::path target_;
  std::filesystem::path stage_;
};

}  // namespace beadtwin
