#include "gcode/annotations.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <utility>

namespace beadtwin::gcode {
namespace {

struct TypeName {
  std::string_view name;
  Feature feature;
  int pass;
};

// TYPE: names of PrusaSlicer (and Slic3r) and Cura.
constexpr std::array<TypeName, 29> kTypes = {{
    {"External perimeter", Feature::kBoundary, 0},
    {"Perimeter", Feature::kBoundary, -1},
    {"Overhang perimeter", Feature::kBoundary, -1},
    {"Internal infill", Feature::kFill, -1},
    {"Solid infill", Feature::kFill, -1},
    {"Top solid infill", Feature::kFill, -1},
    {"Bridge infill", Feature::kFill, -1},
    {"Internal bridge infill", Feature::kFill, -1},
    {"Ironing", Feature::kFill, -1},
    {"Gap fill", Feature::kThinWall, -1},
    {"Skirt", Feature::kPrime, -1},
    {"Skirt/Brim", Feature::kPrime, -1},
    {"Brim", Feature::kRaft, -1},
    {"Wipe tower", Feature::kPrime, -1},
    {"Support material", Feature::kUnknown, -1},
    {"Support material interface", Feature::kUnknown, -1},
    {"Custom", Feature::kUnknown, -1},
    {"Mixed", Feature::kUnknown, -1},
    {"WALL-OUTER", Feature::kBoundary, 0},
    {"WALL-INNER", Feature::kBoundary, -1},
    {"SKIN", Feature::kFill, -1},
    {"FILL", Feature::kFill, -1},
    {"SKIRT", Feature::kPrime, -1},
    {"PRIME-TOWER", Feature::kPrime, -1},
    {"RAFT", Feature::kRaft, -1},
    {"SUPPORT", Feature::kUnknown, -1},
    {"SUPPORT-INTERFACE", Feature::kUnknown, -1},
    {"SUPPORT-INFILL", Feature::kUnknown, -1},
    {"SUPPORT-ROOF", Feature::kUnknown, -1},
}};

// Whole comments that name a feature: ORNL Slicer 2's regions and beadtwin's feature comments.
constexpr std::array<TypeName, 14> kRegions = {{
    {"PERIMETER", Feature::kBoundary, 0},
    {"INSET", Feature::kBoundary, -1},
    {"INFILL", Feature::kFill, -1},
    {"SKIN", Feature::kFill, -1},
    {"SKELETON", Feature::kThinWall, -1},
    {"SUPPORT", Feature::kUnknown, -1},
    {"unknown", Feature::kUnknown, -1},
    {"raft", Feature::kRaft, -1},
    {"fill", Feature::kFill, -1},
    {"lead-in", Feature::kLeadIn, -1},
    {"lead-out", Feature::kLeadOut, -1},
    {"coast", Feature::kCoast, -1},
    {"stock-on-top", Feature::kStockOnTop, -1},
    {"thin-wall", Feature::kThinWall, -1},
}};

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// The number `s` holds (spaces around it allowed, nothing else).
std::optional<double> number(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

bool starts_with(std::string_view s, std::string_view prefix) {
  return s.substr(0, prefix.size()) == prefix;
}

// beadtwin's layer comment: "LAYER 3 SECTION base Z 12.5 HEIGHT 2.5 TIME 40.1 S".
bool read_own_layer(std::string_view c, Annotation& a) {
  if (!starts_with(c, "LAYER ") || c.find(" SECTION ") == std::string_view::npos) return false;
  a.layer_marker = true;
  const std::size_t at = c.find(" HEIGHT ");
  if (at == std::string_view::npos) return true;
  std::string_view rest = c.substr(at + 8);
  rest = rest.substr(0, rest.find(' '));
  a.height = number(rest);
  a.height_in_program_units = true;
  if (!a.height) a.malformed = std::string(c);
  return true;
}

void read_number(std::string_view c, std::size_t prefix, std::optional<double>& into, Annotation& a) {
  into = number(c.substr(prefix));
  if (!into || !(*into > 0.0)) {
    into.reset();
    a.malformed = std::string(c);
  }
}

}  // namespace

Annotation read_annotation(std::string_view comment) {
  Annotation a;
  const std::string_view c = trim(comment);
  if (c == "LAYER_CHANGE" || starts_with(c, "BEGINNING LAYER")) {
    a.layer_marker = true;
  } else if (starts_with(c, "LAYER:")) {
    a.layer_marker = number(c.substr(6)).has_value();
  } else if (read_own_layer(c, a)) {
  } else if (starts_with(c, "HEIGHT:")) {
    read_number(c, 7, a.height, a);
  } else if (starts_with(c, "WIDTH:")) {
    read_number(c, 6, a.width_mm, a);
  } else if (starts_with(c, "TYPE:")) {
    const std::string_view name = trim(c.substr(5));
    a.feature = Feature::kUnknown;
    bool known = false;
    for (const TypeName& t : kTypes) {
      if (!equal_ignoring_case(name, t.name)) continue;
      a.feature = t.feature;
      a.pass = t.pass;
      known = true;
      break;
    }
    if (!known) a.unknown_type = std::string(name);
  } else if (starts_with(c, "BOUNDARY PASS ")) {
    const std::optional<double> n = number(c.substr(14));
    if (n && *n >= 1.0 && *n == std::floor(*n)) {
      a.feature = Feature::kBoundary;
      a.pass = static_cast<int>(*n) - 1;
    }
  } else {
    for (const TypeName& t : kRegions) {
      if (c != t.name) continue;
      a.feature = t.feature;
      a.pass = t.pass;
      break;
    }
  }
  return a;
}

}  // namespace beadtwin::gcode
