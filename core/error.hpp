// Errors: one small hierarchy, the user's apart from ours.
//
// InputError is the user's: a scenario, mesh or program that cannot be used. It carries where the problem
// is (file, line, column, key) and what was expected; `beadtwin` prints it and exits with code 2.
// InternalError is ours: a broken invariant. `beadtwin` prints it and exits with code 3.
// Library code throws; it never calls exit().
#pragma once

#include <stdexcept>
#include <string>

namespace beadtwin {

struct SourceLocation {
  std::string file;  // path as the user gave it; empty when the input has no file (embedded scenario)
  int line = 0;      // 1-based; 0 when unknown
  int column = 0;    // 1-based; 0 when unknown
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string key, std::string message);
  explicit InputError(std::string message) : InputError({}, {}, std::move(message)) {}

  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  SourceLocation where_;
  std::string key_;
  std::string message_;
};

class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// "file:line:column: key: message", leaving out what is unknown.
std::string format_input_error(const SourceLocation& where, const std::string& key,
                               const std::string& message);

}  // namespace beadtwin

// Invariant checks that print both operands. Always on: they guard cheap facts.
#define BT_CHECK(cond)                                                                         \
  do {                                                                                         \
    if (!(cond))                                                                               \
      throw ::beadtwin::InternalError(std::string(__FILE__) + ":" + std::to_string(__LINE__) + \
                                      ": check failed: " #cond);                               \
  } while (0)

#define BT_CHECK_OP(a, op, b)                                                                             \
  do {                                                                                                    \
    const auto bt_a_ = (a);                                                                               \
    const auto bt_b_ = (b);                                                                               \
    if (!(bt_a_ op bt_b_))                                                                                \
      throw ::beadtwin::InternalError(std::string(__FILE__) + ":" + std::to_string(__LINE__) +            \
                                      ": check failed: " #a " " #op " " #b " (" + std::to_string(bt_a_) + \
                                      " vs " + std::to_string(bt_b_) + ")");                              \
  } while (0)
