#include "scenarios/report_parameters.hpp"

#include <algorithm>
#include <cctype>

#include "slicer/section_params.hpp"

namespace beadtwin::scenarios {

using nlohmann::json;

json to_json(const ParamValue& value) {
  return std::visit(
      [](const auto& v) -> json {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return nullptr;
        } else if constexpr (std::is_same_v<T, ParamValue::List>) {
          json out = json::array();
          for (const ParamValue& x : v) out.push_back(to_json(x));
          return out;
        } else {
          return v;
        }
      },
      value.value);
}

std::string report_name(std::string_view leaf, Dimension dim) {
  std::string unit(internal_unit(dim));
  std::replace(unit.begin(), unit.end(), '/', '_');
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return std::tolower(c); });
  if (unit.empty() || leaf.ends_with(unit)) return std::string(leaf);
  return std::string(leaf) + "_" + unit;
}

namespace {

// Every declared key of `table` that has a member, under its report name and nested by its dots.
template <class B>
json declared_json(std::span<const Param<B>> table, const B& block) {
  json out = json::object();
  for (const Param<B>& p : table) {
    if (!p.member) continue;
    json* at = &out;
    std::string_view key = p.key;
    for (std::size_t dot = key.find('.'); dot != std::string_view::npos; dot = key.find('.')) {
      at = &(*at)[std::string(key.substr(0, dot))];
      key.remove_prefix(dot + 1);
    }
    (*at)[report_name(key, p.dim)] = to_json(p.get(block));
  }
  return out;
}

json section_json(const slicer::SectionParams& s) {
  json out = declared_json(slicer::section_params(), s);
  out["z_mm"] = {s.z_min_mm, s.z_max_mm};
  if (!s.fill.enabled) out["fill"] = "none";
  return out;
}

}  // namespace

json parameters_json(const Variant& v) {
  if (v.program)
    return {{"machine", v.machine.name},
            {"material", v.material.name},
            {"program", v.program_file.string()},
            {"program_read", v.program_summary},
            {"voxel_size_mm", v.output.voxel_size_mm},
            {"overrides", v.overrides}};
  json sections = json::array();
  for (const slicer::SectionParams& s : v.sections) sections.push_back(section_json(s));
  return {{"machine", v.machine.name}, {"material", v.material.name},
          {"part", v.part.describe()}, {"voxel_size_mm", v.output.voxel_size_mm},
          {"overrides", v.overrides},  {"sections", sections}};
}

}  // namespace beadtwin::scenarios
