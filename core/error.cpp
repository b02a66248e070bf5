#include "core/error.hpp"

#include <fmt/format.h>

namespace beadtwin {

std::string format_input_error(const SourceLocation& where, const std::string& key,
                               const std::string& message) {
  std::string out;
  if (!where.file.empty()) out += where.file;
  if (where.line > 0) {
    out += fmt::format("{}{}", out.empty() ? "line " : ":", where.line);
    if (where.column > 0) out += fmt::format(":{}", where.column);
  }
  if (!out.empty()) out += ": ";
  if (!key.empty()) out += key + ": ";
  out += message;
  return out;
}

InputError::InputError(SourceLocation where, std::string key, std::string message)
    : std::runtime_error(format_input_error(where, key, message)),
      where_(std::move(where)),
      key_(std::move(key)),
      message_(std::move(message)) {}

}  // namespace beadtwin
