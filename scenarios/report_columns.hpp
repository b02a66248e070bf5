// The variants side by side, as report.html's variants table and summary.md show them: the columns, each a
// declared metric (scenarios/input/metrics.hpp) with its heading and how its value is written, and each
// cell's difference from the baseline variant's, better or worse as the metric's declaration says.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "scenarios/input/result.hpp"

namespace beadtwin::scenarios {

struct VariantColumn {
  std::string_view metric;  // a part-wide metric's name (metric_defs())
  std::string_view heading;
  std::string (*text)(double value);
  bool in_summary = true;  // also in summary.md, which stays short enough for a pull-request comment
};

// The columns, in the tables' order.
std::span<const VariantColumn> variant_columns();

// A cell: the value as written, and its difference from the baseline's where it differs (in points for a
// fraction, else per cent), judged -1 worse, +1 better, 0 neither.
struct VariantCell {
  std::string text;   // "—" without a value
  std::string delta;  // "+1.5 %", "-2.0 pt"; empty where it does not differ or for the baseline itself
  int judgement = 0;
};

// Column `c`'s cell for a variant's metrics `m`, against the baseline variant's (nullptr for the baseline's
// own row).
VariantCell variant_cell(const VariantColumn& c, const Metrics& m, const Metrics* baseline);

}  // namespace beadtwin::scenarios
