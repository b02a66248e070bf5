// What a sweep runs (`beadtwin sweep`, scenarios/sweep.hpp): the axes of its --set options, the
// combinations of a file, the points they expand to, and the metrics it sorts and plots by. Input reading
// only (scenario_input library, fuzzed by tests/fuzz/fuzz_sweep.cpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/input/scenario.hpp"

namespace beadtwin::scenarios {

// At most this many variants in one sweep: a full factorial grows as the product of its axes, and a typo
// (a value list pasted twice) should stop before it queues a month of runs.
constexpr std::size_t kMaxSweepVariants = 100'000;

// One parameter the sweep varies: --set KEY=V1,V2,... (a single value sets it for every variant).
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;  // YAML texts, in the order given
};

// Parses "KEY=V1,V2,...". Values are split at the commas outside brackets, braces and quotes, so
// `origin=[0, 5],[10, 5]` is two values. Throws InputError (key --set) for no '=', no key or an empty value.
SweepAxis parse_sweep_axis(const std::string& text);

// The combinations listed in a file: a YAML list of maps {KEY: VALUE, ...}, each one variant's settings
// (or a map whose `combinations:` is such a list). Throws InputError naming the file, line and what was
// expected.
std::vector<std::vector<Setting>> load_sweep_combinations(const std::filesystem::path& path);
// The same from the file's text; `file` names it in messages.
std::vector<std::vector<Setting>> parse_sweep_combinations(const std::string& text, const std::string& file);

// One variant of a sweep.
struct SweepPoint {
  std::string name;               // v001, v002, ... in the order of the expansion
  std::vector<Setting> settings;  // applied to the base variant in this order
};

// Every point: each combination of `rows` (a single empty one when there are none) crossed with the full
// factorial of `axes`, the first axis varying slowest. Throws InputError (key --set) when there would be
// more than kMaxSweepVariants points or when a point would set one key twice (an axis and a row both
// setting it).
std::vector<SweepPoint> expand_sweep(const std::vector<SweepAxis>& axes,
                                     const std::vector<std::vector<Setting>>& rows);

// A metric the report sorts by or plots, and which way is better: "porosity" (smaller is better) or
// "interfaces.min_healing:max" (larger is better).
struct Objective {
  std::string metric;
  bool maximise = false;
  std::string text() const { return maximise ? metric + ":max" : metric; }
  // Whether `a` is strictly better than `b`.
  bool better(double a, double b) const { return maximise ? a > b : a < b; }
};
// Parses "METRIC" or "METRIC:min|max"; `option` names the command-line option for messages. Throws
// InputError for a name that is not a gate metric (gate_metrics(), sections.NAME.FIGURE).
Objective parse_objective(const std::string& text, const std::string& option);

}  // namespace beadtwin::scenarios
