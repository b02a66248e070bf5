// Headless Chromium driven over the DevTools protocol, for tests that look at a page as a browser shows it.
//
// The browser is started with --remote-debugging-pipe: it reads the protocol's JSON messages, each ended by
// a '\0', on its fd 3 and writes its own on fd 4 (https://chromedevtools.github.io/devtools-protocol/).
// Every read has a deadline, so a browser that hangs fails the test instead of hanging ctest, and the
// browser and the processes it started are killed and reaped when the Chromium object goes, however the
// test ends (its crash handler, which detaches from them, exits by itself once the browser is gone); if the
// test process itself is killed (a ctest timeout), the kernel kills the browser.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/read_file.hpp"

namespace beadtwin::testing {

// The first of `names` found as an executable on PATH, or an empty path.
inline std::filesystem::path find_on_path(std::initializer_list<std::string_view> names) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  for (const std::string_view name : names) {
    std::string_view dirs = path;
    while (!dirs.empty()) {
      const std::size_t colon = dirs.find(':');
      const std::string_view dir = dirs.substr(0, colon);
      dirs = colon == std::string_view::npos ? std::string_view() : dirs.substr(colon + 1);
      if (dir.empty()) continue;
      const std::filesystem::path candidate = std::filesystem::path(dir) / name;
      if (::access(candidate.c_str(), X_OK) == 0 && !std::filesystem::is_directory(candidate))
        return candidate;
    }
  }
  return {};
}

// The bytes that base64 text (RFC 4648, as the protocol sends binary data) stands for. Throws
// std::runtime_error on a character outside the alphabet.
inline std::string base64_decode(std::string_view text) {
  std::string out;
  out.reserve(text.size() / 4 * 3);
  unsigned bits = 0;
  int count = 0;
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (const char c : text) {
    if (c == '=') break;
    const std::size_t v = kAlphabet.find(c);
    if (v == std::string_view::npos)
      throw std::runtime_error("base64: unexpected character " + std::to_string(static_cast<int>(c)));
    bits = (bits << 6 | static_cast<unsigned>(v)) & 0xffffffu;
    count += 6;
    if (count >= 8) {
      count -= 8;
      out.push_back(static_cast<char>((bits >> count) & 0xffu));
    }
  }
  return out;
}

// A file:// URL for an absolute path, with every byte outside the unreserved set percent-encoded.
inline std::string file_url(const std::filesystem::path& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string url = "file://";
  for (const char c : std::filesystem::absolute(path).string()) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      url += c;
    } else {
      url += '%';
      url += kHex[u >> 4];
      url += kHex[u & 15];
    }
  }
  return url;
}

class Chromium {
 public:
  using Clock = std::chrono::steady_clock;

  // Starts `exe` headless with a fresh profile in `profile_dir` (created if missing); the browser's own
  // output (stdout and stderr) goes to `log`. `timeout` bounds each wait for a reply or an event. Throws
  // std::runtime_error when the browser cannot be started.
  Chromium(const std::filesystem::path& exe, const std::filesystem::path& profile_dir,
           const std::filesystem::path& log, std::chrono::milliseconds timeout)
      : log_(log), timeout_(timeout) {
    std::filesystem::create_directories(profile_dir);
    // Sockets rather than pipes, so that a write to a browser that has died fails with EPIPE under
    // MSG_NOSIGNAL instead of raising SIGPIPE in the test; the browser reads and writes them as it would
    // pipes. Every descriptor the child is given is moved above fd 4 and closed on exec, so that none is
    // overwritten by the child's dup2 onto 3 and 4, and each dup2 makes a new one that survives the exec.
    int to_browser[2], from_browser[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, to_browser) != 0 ||
        ::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, from_browser) != 0)
      throw std::runtime_error("chromium: socketpair failed");
    int log_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (log_fd < 0) throw std::runtime_error("chromium: cannot write " + log.string());
    for (int* fd : {&to_browser[0], &to_browser[1], &from_browser[0], &from_browser[1], &log_fd}) {
      const int moved = ::fcntl(*fd, F_DUPFD_CLOEXEC, 10);
      ::close(*fd);
      if (moved < 0) throw std::runtime_error("chromium: out of file descriptors");
      *fd = moved;
    }

    // Everything the child needs is built before the fork: after it, only async-signal-safe calls.
    std::vector<std::string> args = {
        exe.string(),
        "--headless",
        // Chromium refuses to run as root with its sandbox, and containers often lack the namespaces it
        // needs; the page is our own report.
        "--no-sandbox",
        "--disable-gpu",
        "--remote-debugging-pipe",
        "--user-data-dir=" + profile_dir.string(),
        "--no-first-run",
        "--no-default-browser-check",
        "--disable-extensions",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        // Shared memory in /tmp: a container's /dev/shm is often too small for it. (Debian's wrapper script
        // means to add this itself when it is, but its test breaks where /dev/shm is mounted twice.)
        "--disable-dev-shm-usage",
        "--mute-audio",
        "--hide-scrollbars",
        // Screenshots in the page's own sRGB, whatever the machine's display profile.
        "--force-color-profile=srgb",
        "about:blank",
    };
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    // Chromium puts its singleton socket in a folder under TMPDIR, and a socket's path must fit in 108
    // bytes: a test's own TMPDIR deep in a build tree does not leave room, so the browser gets /tmp.
    std::vector<std::string> env = {"TMPDIR=/tmp"};
    for (char** e = environ; *e; ++e)
      if (std::string_view(*e).substr(0, 7) != "TMPDIR=") env.emplace_back(*e);
    std::vector<char*> envp;
    for (std::string& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    const pid_t parent = ::getpid();

    pid_ = ::fork();
    if (pid_ == 0) {
      // Its own process group, so the destructor can kill the browser's helpers with it, and killed when
      // the test process dies (the wrapper script execs the browser, which keeps the setting).
      ::setpgid(0, 0);
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(127);
      if (::dup2(log_fd, 1) < 0 || ::dup2(log_fd, 2) < 0 || ::dup2(to_browser[1], 3) < 0 ||
          ::dup2(from_browser[1], 4) < 0)
        ::_exit(127);
      ::execve(argv[0], argv.data(), envp.data());
      ::_exit(127);
    }
    if (pid_ > 0) ::setpgid(pid_, pid_);  // as the child does, whichever runs first
    ::close(to_browser[1]);
    ::close(from_browser[1]);
    ::close(log_fd);
    to_browser_ = to_browser[0];
    from_browser_ = from_browser[0];
    if (pid_ < 0) {
      stop();
      throw std::runtime_error("chromium: fork failed");
    }
  }

  ~Chromium() { stop(); }
  Chromium(const Chromium&) = delete;
  Chromium& operator=(const Chromium&) = delete;

  // Sends the command `method` (to the browser, or to the page attached as `session`) and returns its
  // result. Events that arrive meanwhile are kept. Throws std::runtime_error with the browser's message
  // when the command fails, and when no reply comes in time.
  nlohmann::json call(const std::string& method, const nlohmann::json& params = nlohmann::json::object(),
                      const std::string& session = {}) {
    const int id = next_id_++;
    nlohmann::json message = {{"id", id}, {"method", method}, {"params", params}};
    if (!session.empty()) message["sessionId"] = session;
    const Clock::time_point deadline = Clock::now() + timeout_;
    send(message.dump(), deadline);
    for (;;) {
      nlohmann::json reply = receive(deadline, method);
      if (!reply.contains("id")) {
        events_.push_back(std::move(reply));
      } else if (reply["id"] == id) {
        if (reply.contains("error")) throw std::runtime_error(method + " failed: " + reply["error"].dump());
        return reply.value("result", nlohmann::json::object());
      }
    }
  }

  // Waits for the event `method` of `session` that is at position `from` or later in events(), and returns
  // it. Throws std::runtime_error when none comes in time.
  nlohmann::json wait_for(const std::string& method, const std::string& session, std::size_t from) {
    const Clock::time_point deadline = Clock::now() + timeout_;
    for (std::size_t i = from;; ++i) {
      while (i >= events_.size()) {
        nlohmann::json message = receive(deadline, method);
        if (!message.contains("id")) events_.push_back(std::move(message));
      }
      if (events_[i].value("method", "") == method && events_[i].value("sessionId", "") == session)
        return events_[i];
    }
  }

  // Every event received so far, in order, as the browser sent it: {"method", "params", "sessionId"}.
  const std::vector<nlohmann::json>& events() const { return events_; }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    std::string tail = read_file(log_);
    if (tail.size() > 4000) tail = "..." + tail.substr(tail.size() - 4000);
    throw std::runtime_error("chromium: " + what + "; its output (" + log_.string() + "):\n" + tail);
  }

  static int remaining_ms(Clock::time_point deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    return static_cast<int>(std::max<std::chrono::milliseconds::rep>(left.count(), 0));
  }

  void send(std::string text, Clock::time_point deadline) {
    text.push_back('\0');
    std::size_t sent = 0;
    while (sent < text.size()) {
      pollfd p{to_browser_, POLLOUT, 0};
      const int ready = ::poll(&p, 1, remaining_ms(deadline));
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0) fail("it took no message within the timeout");
      const ssize_t n = ::send(to_browser_, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fail("it stopped reading (exited?)");
      sent += static_cast<std::size_t>(n);
    }
  }

  // The next whole message, waiting for it until `deadline`; `waiting_for` names what for, in the error.
  nlohmann::json receive(Clock::time_point deadline, const std::string& waiting_for) {
    for (;;) {
      const std::size_t end = buffer_.find('\0', scanned_);
      if (end != std::string::npos) {
        nlohmann::json message = nlohmann::json::parse(buffer_.begin(), buffer_.begin() + end);
        buffer_.erase(0, end + 1);
        scanned_ = 0;
        return message;
      }
      scanned_ = buffer_.size();
      pollfd p{from_browser_, POLLIN, 0};
      const int ready = ::poll(&p, 1, remaining_ms(deadline));
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0)
        fail("no reply within " + std::to_string(timeout_.count()) + " ms waiting for " + waiting_for);
      char chunk[65536];
      const ssize_t n = ::read(from_browser_, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) fail("it closed the pipe (exited?) while we waited for " + waiting_for);
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  // Kills the browser's whole process group and reaps the browser. Its group outlives it as long as the
  // unreaped browser holds it, so the kill cannot reach anyone else's processes.
  void stop() noexcept {
    if (pid_ > 0) {
      ::kill(-pid_, SIGKILL);
      ::kill(pid_, SIGKILL);  // in case it died before it made its group
      while (::waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {
      }
      pid_ = -1;
    }
    for (int* fd : {&to_browser_, &from_browser_})
      if (*fd >= 0) {
        ::close(*fd);
        *fd = -1;
      }
  }

  std::filesystem::path log_;
  std::chrono::milliseconds timeout_;
  pid_t pid_ = -1;
  int to_browser_ = -1, from_browser_ = -1;
  int next_id_ = 1;
  std::string buffer_;       // bytes read but not yet a whole message
  std::size_t scanned_ = 0;  // of buffer_, known to hold no '\0'
  std::vector<nlohmann::json> events_;
};

}  // namespace beadtwin::testing
