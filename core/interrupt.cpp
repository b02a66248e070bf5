#include "core/interrupt.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <string>
#include <system_error>

#include <signal.h>
#include <unistd.h>

namespace beadtwin {
namespace {

// Two buffers: the writer fills the one the handler is not reading, then publishes its index.
constexpr std::size_t kContextBytes = 200;
std::array<std::array<char, kContextBytes + 1>, 2> g_context{};
std::atomic<int> g_current{-1};

void write_all(const char* s) {
  std::size_t left = std::strlen(s);
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, s, left);
    if (n <= 0) return;
    s += n;
    left -= static_cast<std::size_t>(n);
  }
}

// Only async-signal-safe calls: write(2) and _exit(2).
extern "C" void on_signal(int sig) {
  write_all(sig == SIGINT ? "\ninterrupted" : "\nterminated");
  const int i = g_current.load();
  if (i >= 0) {
    write_all(": stopped during ");
    write_all(g_context[static_cast<std::size_t>(i)].data());
  }
  write_all("; the output directory keeps the previous run's reports, untouched\n");
  ::_exit(128 + sig);
}

}  // namespace

void install_interrupt_handler() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void set_interrupt_context(std::string_view what) {
  const int next = g_current.load() == 0 ? 1 : 0;
  auto& buf = g_context[static_cast<std::size_t>(next)];
  const std::size_t n = std::min(what.size(), kContextBytes);
  std::memcpy(buf.data(), what.data(), n);
  buf[n] = '\0';
  g_current.store(next);
}

int remove_stale_temporaries(const std::filesystem::path& dir) {
  int removed = 0;
  const auto sweep = [&](const std::filesystem::path& folder) {
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(folder, ec)) {
      const std::string name = e.path().filename().string();
      if (!name.starts_with(".tmp-")) continue;
      const std::size_t dash = name.find('-', 5);
      if (dash == std::string::npos) continue;
      long pid = 0;
      try {
        pid = std::stol(name.substr(5, dash - 5));
      } catch (const std::exception&) {
        continue;
      }
      // A process that is still running (another run into the same folder) keeps its files.
      if (pid <= 0 || (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM)) continue;
      std::error_code rm;  // a file, or a run's staging folder (StagedDir)
      if (std::filesystem::remove_all(e.path(), rm) > 0) ++removed;
    }
  };
  sweep(dir);
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.is_directory(ec)) sweep(e.path());
  return removed;
}

}  // namespace beadtwin
