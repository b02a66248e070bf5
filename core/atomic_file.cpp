#include "core/atomic_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/interrupt.hpp"

namespace beadtwin {
namespace {

// This process's temporary name for `what`: ".tmp-PID-what", the form remove_stale_temporaries recognises.
std::string temporary_name(const std::string& what) {
  return fmt::format(".tmp-{}-{}", ::getpid(), what);
}

}  // namespace

AtomicPath::AtomicPath(std::filesystem::path target) : target_(std::move(target)) {
  // Keep the extension last: image writers choose the format from it.
  temp_ = target_.parent_path() / temporary_name(target_.filename().string());
}

AtomicPath::~AtomicPath() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicPath::commit() {
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec)
    throw std::runtime_error("cannot move " + temp_.string() + " to " + target_.string() + ": " +
                             ec.message());
  committed_ = true;
}

AtomicStream::AtomicStream(std::filesystem::path target) : path_(std::move(target)) {
  out_.open(path_.temp(), std::ios::binary | std::ios::trunc);
  if (!out_)
    throw std::runtime_error("cannot write " + path_.target().string() + ": " +
                             std::generic_category().message(errno));
}

void AtomicStream::commit() {
  out_.flush();
  if (!out_) throw std::runtime_error("error while writing " + path_.target().string());
  out_.close();
  if (!out_) throw std::runtime_error("error while closing " + path_.target().string());
  path_.commit();
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  AtomicPath out(path);
  {
    std::ofstream f(out.temp(), std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("cannot write " + out.temp().string());
    f.write(content.data(), static_cast<std::streamsize>(content.size()));
    f.flush();
    if (!f) throw std::runtime_error("error while writing " + out.temp().string());
  }
  out.commit();
}

StagedDir::StagedDir(std::filesystem::path target)
    : target_(std::move(target)), stage_(target_ / temporary_name("run")) {
  std::error_code ec;
  std::filesystem::remove_all(stage_, ec);
  std::filesystem::create_directories(stage_, ec);
  if (ec) throw std::runtime_error("cannot make " + stage_.string() + ": " + ec.message());
}

StagedDir::~StagedDir() {
  std::error_code ec;
  std::filesystem::remove_all(stage_, ec);
}

void StagedDir::commit(const std::vector<std::string>& last) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(stage_, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
    if (it->is_regular_file()) files.push_back(std::filesystem::relative(it->path(), stage_));
  if (ec) throw std::runtime_error("cannot list " + stage_.string() + ": " + ec.message());
  // Every file not named in `last`, in name order; then those named, in the order given.
  std::sort(files.begin(), files.end());
  std::vector<std::filesystem::path> order;
  for (const auto& f : files)
    if (std::find(last.begin(), last.end(), f.generic_string()) == last.end()) order.push_back(f);
  for (const std::string& name : last)
    if (std::find(files.begin(), files.end(), std::filesystem::path(name)) != files.end())
      order.emplace_back(name);
  for (const std::filesystem::path& f : order) {
    const std::filesystem::path to = target_ / f;
    std::filesystem::create_directories(to.parent_path(), ec);
    std::filesystem::rename(stage_ / f, to, ec);
    if (ec)
      throw std::runtime_error("cannot move " + (stage_ / f).string() + " to " + to.string() + ": " +
                               ec.message());
  }
}

void prepare_output_dir(const std::filesystem::path& dir, const std::string& option) {
  const auto refuse = [&](const std::string& why) {
    throw InputError(
        {dir.string(), 0, 0}, option,
        fmt::format("cannot write the output here: {}; choose a writable directory with {}", why, option));
  };
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) refuse(ec.message());
  if (!std::filesystem::is_directory(dir, ec)) refuse("not a directory");
  // Whether files can be made here (permissions, a read-only file system): a probe, removed at once.
  const std::filesystem::path probe = dir / temporary_name("probe");
  {
    std::ofstream f(probe, std::ios::binary | std::ios::trunc);
    if (!f) refuse(std::error_code(errno, std::generic_category()).message());
  }
  std::filesystem::remove(probe, ec);
  remove_stale_temporaries(dir);  // what an interrupted run left half-written
}

}  // namespace beadtwin
