// Every scenario parameter declared once (STYLE.md rule 4): key, type, unit, range, default, meaning and
// where it comes from. The loader reads through these tables, so validation, defaults and documentation
// can never disagree.
#pragma once

#include <limits>
#include <span>
#include <string>
#include <string_view>

#include "core/units.hpp"

namespace beadtwin::scenarios {

enum class ParamType { kQuantity, kInteger, kBool, kString };

struct ParamSpec {
  std::string_view key;  // dotted path inside its block ("boundary.passes")
  ParamType type = ParamType::kQuantity;
  Dimension dim = Dimension::kDimensionless;
  std::string_view default_text;  // empty: required
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;  // the value must be strictly above min
  std::string_view meaning;
  std::string_view source;  // patent paragraph, paper, or "estimate"
  bool derived = false;     // absent means "derived from other parameters" (the meaning says how)
};

// The blocks of a scenario and of the machine and material files.
std::span<const ParamSpec> section_params();
std::span<const ParamSpec> machine_params();
std::span<const ParamSpec> material_params();
std::span<const ParamSpec> output_params();
std::span<const ParamSpec> thermal_params();
std::span<const ParamSpec> tool_params();
std::span<const ParamSpec> render_params();
std::span<const ParamSpec> image_params();

}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {

// Every parameter table as Markdown: what `beadtwin params` prints and docs/parameters.md holds.
std::string params_markdown();

}  // namespace beadtwin::scenarios
