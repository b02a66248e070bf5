// Fnv1a against the published FNV-1a 64-bit test vectors (Fowler, Noll and Vo; the reference test suite
// of the FNV hash, test vectors for "", "a" and "foobar").
#include "core/hash.hpp"

#include <cstdint>
#include <cstring>
#include <string_view>

#include <gtest/gtest.h>

namespace beadtwin {
namespace {

TEST(Fnv1a, MatchesThePublishedVectors) {
  EXPECT_EQ(Fnv1a().value(), 0xcbf29ce484222325ull);
  EXPECT_EQ(Fnv1a().add("a").value(), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(Fnv1a().add("foobar").value(), 0x85944171f73967e8ull);
  EXPECT_EQ(Fnv1a().add("foo").add("bar").value(), Fnv1a().add("foobar").value());  // in pieces, the same
  EXPECT_EQ(Fnv1a().add("foobar").hex(), "85944171f73967e8");
}

TEST(Fnv1a, TakesAValuesBytes) {
  const std::uint32_t one = 1;
  char bytes[sizeof one];
  std::memcpy(bytes, &one, sizeof one);
  EXPECT_EQ(Fnv1a().add_value(one).value(), Fnv1a().add(std::string_view(bytes, sizeof bytes)).value());
  EXPECT_NE(Fnv1a().add_value(one).value(), Fnv1a().add_value(std::uint32_t{2}).value());
}

}  // namespace
}  // namespace beadtwin
