// A stable 64-bit hash of bytes (FNV-1a, Fowler, Noll and Vo): the same value on every machine, build and
// run, for fingerprints that are compared or stored (a sweep's plan, the part each MPI rank solves). Not for
// hash tables under attack, nor as a checksum against tampering.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

namespace beadtwin {

// The hash of everything added so far, in order: h.add(a).add(b) hashes the bytes of a then b.
class Fnv1a {
 public:
  Fnv1a& add(std::string_view bytes) {
    for (const char c : bytes) h_ = (h_ ^ static_cast<unsigned char>(c)) * kPrime;
    return *this;
  }
  // The bytes of a trivially copyable value (a number, a flag) as this machine holds them.
  template <class T>
  requires std::is_trivially_copyable_v<T> Fnv1a& add_value(const T& value) {
    char bytes[sizeof value];
    std::memcpy(bytes, &value, sizeof value);
    return add(std::string_view(bytes, sizeof bytes));
  }
  std::uint64_t value() const { return h_; }
  // The value as 16 hex digits.
  std::string hex() const { return fmt::format("{:016x}", h_); }

 private:
  static constexpr std::uint64_t kOffsetBasis = 14695981039346656037ull;
  static constexpr std::uint64_t kPrime = 1099511628211ull;
  std::uint64_t h_ = kOffsetBasis;
};

}  // namespace beadtwin
