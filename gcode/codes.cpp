// Machine codes and the reader's options: parsing, validation, defaults.
#include "gcode/codes.hpp"

#include <charconv>

#include <fmt/format.h>

#include "core/error.hpp"
#include "gcode/block_reader.hpp"

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
      prime(o.prime, "reader.prime"),
      reverse_on(o.reverse_on, "reader.reverse_on"),
      reverse_off(o.reverse_off, "reader.reverse_off"),
      ignored(o.ignored, "reader.ignored") {}

bool CodeSets::acts_on(const Word& w) const {
  if (w.letter == 'M') {
    const int t = code_tenths(w.value);
    if (t == 20 || t == 300 || t == 820 || t == 830 || t == 2000) return true;
  }
  for (const CodeSet* s : {&melt_on, &melt_off, &heat_on, &heat_off, &roller_down, &roller_up, &prime,
                           &reverse_on, &reverse_off})
    if (s->matches(w)) return true;
  return false;
}

std::vector<std::string> default_ignored_codes() {
  return {// Work offset, cutter and tool length compensation off, canned cycles off, path modes, feed per
          // minute, bed levelling (Marlin G29, Prusa G80): nothing the toolpath records.
          "G29", "G40", "G49", "G54", "G61", "G64", "G80", "G94", "G98", "G99",
          // Program stops, motors, temperatures, fans, messages, firmware settings and queries, progress,
          // object labels, linear advance, Prusa printer checks.
          "M0", "M1", "M17", "M18", "M84", "M104", "M105", "M106", "M107", "M109", "M110", "M114", "M115",
          "M117", "M118", "M119", "M140", "M141", "M190", "M191", "M201", "M202", "M203", "M204", "M205",
          "M206", "M73", "M400", "M420", "M486", "M500", "M501", "M502", "M503", "M851", "M862.1", "M862.3",
          "M900", "M907"};
}

void validate(const ReaderOptions& o) {
  std::vector<std::string> problems;
  try {
    const CodeSets codes(o);
  } catch (const InputError& e) {
    problems.push_back(e.key() + ": " + e.message());
  }
  const auto positive = [&](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v))
      problems.push_back(fmt::format("reader.{} must be positive, got {}", key, v));
  };
  const auto not_negative = [&](double v, const char* key) {
    if (!(v >= 0.0) || !std::isfinite(v))
      problems.push_back(fmt::format("reader.{} must not be negative, got {}", key, v));
  };
  if (!o.volumetric_e) positive(o.filament_diameter_mm, "filament_diameter_mm");
  positive(o.chord_tolerance_mm, "chord_tolerance_mm");
  positive(o.default_feed_mm_s, "default_feed_mm_s");
  positive(o.max_coordinate_mm, "max_coordinate_mm");
  not_negative(o.rapid_feed_mm_s, "rapid_feed_mm_s");
  not_negative(o.default_bead_width_mm, "default_bead_width_mm");
  not_negative(o.default_layer_height_mm, "default_layer_height_mm");
  if (o.default_bead_width_mm > 0.0 && o.default_layer_height_mm > o.default_bead_width_mm)
    problems.push_back(
        fmt::format("reader.default_layer_height_mm ({}) must not exceed default_bead_width_mm ({})",
                    o.default_layer_height_mm, o.default_bead_width_mm));
  if (o.max_moves == 0) problems.push_back("reader.max_moves must be positive");
  if (o.extruder) {
    try {
      beadtwin::validate(*o.extruder);
    } catch (const InputError& e) {
      problems.push_back("reader.extruder: " + e.message());
    }
    if (o.extruder->has_constant_feed() && o.melt_on.empty())
      problems.push_back(
          "reader.extruder: a constant filament feed runs from melt on to melt off, but "
          "reader.melt_on names no code");
  }
  if (problems.empty()) return;
  std::string all = problems.front();
  for (std::size_t i = 1; i < problems.size(); ++i) all += "; " + problems[i];
  throw InputError({}, "reader", all);
}

ReaderOptions reader_options_for(const GcodeDialect& d, const Extruder* extruder) {
  ReaderOptions o;
  const auto codes = [](const std::string& code) {
    return code.empty() ? std::vector<std::string>{} : std::vector<std::string>{code};
  };
  o.melt_on = codes(d.melt_on);
  o.melt_off = codes(d.melt_off);
  o.roller_down = codes(d.roller_down);
  o.roller_up = codes(d.roller_up);
  o.prime = codes(d.prime_code);
  o.reverse_on = codes(d.reverse_on);
  o.reverse_off = codes(d.reverse_off);
  o.inches = d.inches;
  o.rapid_feed_mm_s = d.rapid_feed_mm_s;
  o.dwell_p_seconds = false;  // write_gcode writes G4 P<milliseconds>
  if (extruder) {
    o.extruder = *extruder;
    if (extruder->kind == ExtruderKind::kFilament) o.filament_diameter_mm = extruder->filament_diameter_mm;
  }
  return o;
}

std::size_t ReadStats::warning_count() const {
  std::size_t n = 0;
  for (const auto& [kind, count] : warnings) n += count;
  return n;
}

std::size_t ReadStats::count(const std::string& kind) const {
  const auto it = warnings.find(kind);
  return it == warnings.end() ? 0 : it->second;
}

}  // namespace beadtwin::gcode
