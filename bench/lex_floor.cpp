// The least any G-code reader must spend just to see a program's numbers: the file mapped, and on every line
// the comment skipped and every word's number turned into a double (digits into an integer, over a power
// of ten: exact, as strtod, for the 15 digits or fewer a program's numbers have), split over THREADS threads
// at line ends. Nothing is kept: no modal state, no moves, no motion plan. bench/read_vs_wc.sh compiles it
// on the fly and runs it on the same program as `wc -l` and `beadtwin read`, in the same run.
// Usage: lex_floor FILE THREADS   (prints the wall time in seconds, then what it saw)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

namespace {

constexpr std::array<double, 16> kPow10 = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                           1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};

struct Seen {
  double sum = 0.0;  // of every number, so that none can be skipped unseen
  std::size_t words = 0, lines = 0;
};

Seen lex(const char* p, const char* end) {
  Seen s;
  while (p < end) {
    while (p < end && *p != '\n') {
      const char c = *p;
      if (c == ';' || c == '(') {  // a comment runs to the line's end
        const void* nl = std::memchr(p, '\n', static_cast<std::size_t>(end - p));
        p = nl != nullptr ? static_cast<const char*>(nl) : end;
        break;
      }
      if ((c | 0x20) < 'a' || (c | 0x20) > 'z') {
        ++p;
        continue;
      }
      ++p;  // a word: its letter, then its number
      const char* number = p;
      bool negative = false;
      if (p < end && (*p == '-' || *p == '+')) negative = *p++ == '-';
      std::uint64_t digits = 0;
      int count = 0, decimals = 0;
      while (p < end && static_cast<unsigned>(*p - '0') < 10)
        digits = digits * 10 + static_cast<unsigned>(*p++ - '0'), ++count;
      if (p < end && *p == '.') {
        ++p;
        while (p < end && static_cast<unsigned>(*p - '0') < 10)
          digits = digits * 10 + static_cast<unsigned>(*p++ - '0'), ++count, ++decimals;
      }
      const double value = count <= 15
                               ? static_cast<double>(digits) / kPow10[static_cast<std::size_t>(decimals)]
                               : std::abs(std::strtod(number, nullptr));
      s.sum += negative ? -value : value;
      ++s.words;
    }
    ++s.lines;
    ++p;
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || std::atoi(argv[2]) < 1) {
    std::fprintf(stderr, "usage: lex_floor FILE THREADS\n");
    return 2;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int fd = open(argv[1], O_RDONLY);
  struct stat st {};
  if (fd < 0 || fstat(fd, &st) != 0 || st.st_size <= 0) {
    std::fprintf(stderr, "lex_floor: cannot read %s\n", argv[1]);
    return 2;
  }
  const auto size = static_cast<std::size_t>(st.st_size);
  void* mapped = mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  if (mapped == MAP_FAILED) {
    std::fprintf(stderr, "lex_floor: cannot map %s\n", argv[1]);
    return 2;
  }
  const char* data = static_cast<const char*>(mapped);
  const auto threads = static_cast<std::size_t>(std::atoi(argv[2]));
  std::vector<const char*> cut{data};
  for (std::size_t t = 1; t < threads; ++t) {
    const char* q = cut.back() > data + size * t / threads ? cut.back() : data + size * t / threads;
    const void* nl = std::memchr(q, '\n', static_cast<std::size_t>(data + size - q));
    cut.push_back(nl != nullptr ? static_cast<const char*>(nl) + 1 : data + size);
  }
  cut.push_back(data + size);
  std::vector<Seen> seen(threads);
  std::vector<std::thread> pool;
  for (std::size_t t = 0; t < threads; ++t) pool.emplace_back([&, t] { seen[t] = lex(cut[t], cut[t + 1]); });
  for (std::thread& th : pool) th.join();
  Seen all;
  for (const Seen& s : seen) all.sum += s.sum, all.words += s.words, all.lines += s.lines;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%.4f\n%zu lines, %zu numbers, their sum %.6g\n", s, all.lines, all.words, all.sum);
  return 0;
}
