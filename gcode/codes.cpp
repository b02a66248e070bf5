#include "gcode/codes.hpp"

#include <charconv>

#include <fmt/format.h>

#include "core/error.hpp"
#include "gcode/reader_options.hpp"

namespace beadtwin::gcode {
namespace {

std::optional<MachineCode> parse_code(std::string_view text) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  text = text.substr(0, text.find(' '));  // "M62 P1": the code is the first word
  if (text.size() < 2) return std::nullopt;
  char letter = text.front();
  if (letter >= 'a' && letter <= 'z') letter = static_cast<char>(letter - 'a' + 'A');
  if (letter < 'A' || letter > 'Z') return std::nullopt;
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data() + 1, text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || !(v >= 0.0) || v > 1e6) return std::nullopt;
  return MachineCode{letter, code_tenths(v)};
}

}  // namespace

CodeSet::CodeSet(const std::vector<std::string>& codes, const std::string& key) {
  for (const std::string& c : codes) {
    const std::optional<MachineCode> code = parse_code(c);
    if (!code)
      throw InputError({}, key,
                       fmt::format("'{}' is not a code: expected a letter and a number, such as M23", c));
    codes_.push_back(*code);
  }
}

bool CodeSet::matches(const Word& w) const {
  const int t = code_tenths(w.value);
  for (const MachineCode& c : codes_)
    if (c.letter == w.letter && c.tenths == t) return true;
  return false;
}

CodeSets::CodeSets(const ReaderOptions& o)
    : melt_on(o.melt_on, "reader.melt_on"),
      melt_off(o.melt_off, "reader.melt_off"),
      heat_on(o.heat_on, "reader.heat_on"),
      heat_off(o.heat_off, "reader.heat_off"),
      roller_down(o.roller_down, "reader.roller_down"),
      roller_up(o.roller_up, "reader.roller_up"),
      fan_on(o.fan_on, "reader.fan_on"),
      fan_off(o.fan_off, "reader.fan_off"),
      nozzle_temp(o.nozzle_temp, "reader.nozzle_temp"),
      prime(o.prime, "reader.prime"),
      reverse_on(o.reverse_on, "reader.reverse_on"),
      reverse_off(o.reverse_off, "reader.reverse_off"),
      ignored(o.ignored, "reader.ignored") {}

bool CodeSets::acts_on(const Word& w) const {
  if (w.letter == 'M') {
    const int t = code_tenths(w.value);
    if (t == 20 || t == 300 || t == 820 || t == 830 || t == 2000) return true;
  }
  for (const CodeSet* s : {&melt_on, &melt_off, &heat_on, &heat_off, &roller_down, &roller_up, &fan_on,
                           &fan_off, &nozzle_temp, &prime, &reverse_on, &reverse_off})
    if (s->matches(w)) return true;
  return false;
}

}  // namespace beadtwin::gcode
