#include "gcode/reader_options.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "gcode/codes.hpp"

namespace beadtwin::gcode {

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
  positive(o.fan_full, "fan_full");
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
  if (!o.rpm_word.empty() &&
      std::find(kSpeedWords.begin(), kSpeedWords.end(), o.rpm_word) == kSpeedWords.end())
    problems.push_back(fmt::format(
        "reader.rpm_word must be a letter the reader gives no other meaning ({}) or empty, got '{}'",
        fmt::join(kSpeedWords, ", "), o.rpm_word));
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
  o.heat_on = codes(d.heat_on);
  o.heat_off = codes(d.heat_off);
  o.roller_down = codes(d.roller_down);
  o.roller_up = codes(d.roller_up);
  o.fan_on = codes(d.fan_on);
  o.fan_off = codes(d.fan_off);
  o.fan_full = d.fan_full;
  o.nozzle_temp.clear();
  std::istringstream nozzle_codes(d.nozzle_temp);
  for (std::string code; nozzle_codes >> code;) o.nozzle_temp.push_back(code);
  o.prime = codes(d.prime_code);
  o.reverse_on = codes(d.reverse_on);
  o.reverse_off = codes(d.reverse_off);
  o.rpm_word = d.rpm_word;
  o.inches = d.inches;
  o.rapid_feed_mm_s = d.rapid_feed_mm_s;
  o.dwell_p_seconds = false;  // write_gcode writes G4 P<milliseconds>
  if (extruder) {
    o.extruder = *extruder;
    if (extruder->kind == ExtruderKind::kFilament) o.filament_diameter_mm = extruder->filament_diameter_mm;
  }
  return o;
}

}  // namespace beadtwin::gcode
