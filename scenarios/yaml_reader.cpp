#include "scenarios/yaml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

namespace beadtwin::scenarios {
namespace {

std::vector<std::string> split(std::string_view dotted) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', start);
    parts.emplace_back(dotted.substr(start, dot == std::string_view::npos ? dotted.npos : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// Leaf keys of a map, dotted, with the node of each key (for its location).
void leaves(const YAML::Node& node, const std::string& prefix,
            std::vector<std::pair<std::string, YAML::Node>>& out) {
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string key = prefix.empty() ? it->first.Scalar() : prefix + "." + it->first.Scalar();
    if (it->second.IsMap() && it->second.size() > 0) leaves(it->second, key, out);
    out.emplace_back(key, it->first);
  }
}

}  // namespace

SourceLocation location_of(const YAML::Node& node, const std::string& file) {
  if (!node.IsDefined() || node.Mark().is_null()) return {file, 0, 0};
  return {file, node.Mark().line + 1, node.Mark().column + 1};
}

YAML::Node parse_yaml(const std::string& text, const std::string& file) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError({file, e.mark.line + 1, e.mark.column + 1}, {}, "YAML syntax: " + e.msg);
  }
}

std::map<Dimension, std::string> read_units_block(const YAML::Node& node, const std::string& file) {
  static const std::pair<std::string_view, Dimension> kNames[] = {
      {"length", Dimension::kLength},      {"temperature", Dimension::kTemperature},
      {"time", Dimension::kTime},          {"mass", Dimension::kMass},
      {"speed", Dimension::kSpeed},        {"angle", Dimension::kAngle},
      {"mass_flow", Dimension::kMassFlow}, {"volume_flow", Dimension::kVolumeFlow}};
  std::map<Dimension, std::string> out;
  if (!node.IsDefined() || node.IsNull()) return out;
  if (!node.IsMap())
    throw InputError(location_of(node, file), "units", "expected a map such as {length: in, temperature: C}");
  for (auto it = node.begin(); it != node.end(); ++it) {
    const std::string name = it->first.Scalar();
    const auto found =
        std::find_if(std::begin(kNames), std::end(kNames), [&](const auto& p) { return p.first == name; });
    if (found == std::end(kNames)) {
      std::string names;
      for (const auto& p : kNames) names += (names.empty() ? "" : ", ") + std::string(p.first);
      throw InputError(location_of(it->first, file), "units." + name,
                       "unknown dimension; expected one of: " + names);
    }
    const std::string unit = it->second.Scalar();
    try {
      (void)to_internal(1.0, unit, found->second);
    } catch (const QuantityError& e) {
      throw InputError(location_of(it->second, file), "units." + name, e.what());
    }
    out[found->second] = unit;
  }
  return out;
}

BlockReader::BlockReader(YAML::Node node, std::string prefix, std::shared_ptr<const YamlSource> source,
                         const std::map<std::string, SourceLocation>* overridden)
    : node_(std::move(node)),
      prefix_(std::move(prefix)),
      source_(std::move(source)),
      overridden_(overridden) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap())
    throw InputError(location_of(node_, source_->file), prefix_, "expected a map of keys and values");
}

std::string BlockReader::full_key(std::string_view key) const {
  if (prefix_.empty()) return std::string(key);
  if (key.empty()) return prefix_;
  return prefix_ + "." + std::string(key);
}

SourceLocation BlockReader::where(const YAML::Node& node, std::string_view key) const {
  if (overridden_ && !key.empty()) {
    const auto it = overridden_->find(full_key(key));
    if (it != overridden_->end()) return it->second;
  }
  return location_of(node.IsDefined() ? node : node_, source_->file);
}

void BlockReader::fail(const YAML::Node& node, std::string_view key, const std::string& message) const {
  throw InputError(where(node, key), full_key(key), message);
}

YAML::Node BlockReader::find(std::string_view dotted) const {
  if (!node_.IsDefined() || !node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  YAML::Node cur = node_;
  for (const std::string& part : split(dotted)) {
    if (!cur.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node next = cur[part];
    if (!next.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    cur.reset(next);
  }
  return cur;
}

bool BlockReader::has(std::string_view dotted) const {
  return find(dotted).IsDefined();
}

YAML::Node BlockReader::take(std::string_view dotted) {
  used_.emplace(dotted);
  return find(dotted);
}

double BlockReader::parse(const YAML::Node& node, Dimension dim, const std::string& key) const {
  if (!node.IsScalar())
    fail(node, key, fmt::format("expected a {} (a number with a unit)", dimension_name(dim)));
  const auto unit = source_->default_units.find(dim);
  try {
    return parse_quantity(node.Scalar(), dim,
                          unit == source_->default_units.end() ? std::string_view{} : unit->second);
  } catch (const QuantityError& e) {
    fail(node, key, e.what());
  }
}

void BlockReader::check_range(const ParamSpec& spec, double value, const YAML::Node& node) const {
  const bool low = spec.min_exclusive ? !(value > spec.min) : !(value >= spec.min);
  if (low || !(value <= spec.max)) {
    const std::string unit(internal_unit(spec.dim));
    std::string range;
    if (std::isinf(spec.max))
      range = fmt::format("{} {}{}", spec.min_exclusive ? "above" : "at least", spec.min,
                          unit.empty() ? "" : " " + unit);
    else
      range = fmt::format("in {}{}, {}]{}", spec.min_exclusive ? "(" : "[", spec.min, spec.max,
                          unit.empty() ? "" : " " + unit);
    fail(node, spec.key,
         fmt::format("value {}{} is out of range; expected a value {}", value, unit.empty() ? "" : " " + unit,
                     range));
  }
}

YAML::Node BlockReader::value_or_default(const ParamSpec& spec, bool& from_default) {
  YAML::Node node = take(spec.key);
  from_default = !node.IsDefined() || node.IsNull();
  if (from_default && spec.default_text.empty()) {
    // A misspelling of the key is the likeliest reason: point at it.
    if (node_.IsDefined() && node_.IsMap()) {
      std::vector<std::pair<std::string, YAML::Node>> present;
      leaves(node_, "", present);
      for (const auto& [key, key_node] : present) {
        if (key != spec.key && edit_distance(key, spec.key) <= 2)
          throw InputError(
              where(key_node, key), full_key(key),
              fmt::format("unknown key; did you mean '{}'? (required: {})", spec.key, spec.meaning));
      }
    }
    fail(node_, spec.key, fmt::format("required key is missing ({})", spec.meaning));
  }
  return node;
}

double BlockReader::quantity(const ParamSpec& spec) {
  bool from_default = false;
  YAML::Node node = value_or_default(spec, from_default);
  const double v = from_default ? parse_quantity(spec.default_text, spec.dim)
                                : parse(node, spec.dim, std::string(spec.key));
  if (!from_default) check_range(spec, v, node);
  return v;
}

std::optional<double> BlockReader::optional_quantity(const ParamSpec& spec) {
  YAML::Node node = take(spec.key);
  if (!node.IsDefined() || node.IsNull()) return std::nullopt;
  const double v = parse(node, spec.dim, std::string(spec.key));
  check_range(spec, v, node);
  return v;
}

int BlockReader::integer(const ParamSpec& spec) {
  bool from_default = false;
  YAML::Node node = value_or_default(spec, from_default);
  const long v = from_default ? whole_number(std::string(spec.default_text), node, spec.key)
                              : whole_number(node.IsScalar() ? node.Scalar() : "", node, spec.key);
  if (!from_default) check_range(spec, static_cast<double>(v), node);
  return static_cast<int>(v);
}

long BlockReader::whole_number(const std::string& text, const YAML::Node& node, std::string_view key) const {
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    fail(node, key, fmt::format("expected a whole number but found '{}'", text));
  return v;
}

bool BlockReader::boolean(const ParamSpec& spec) {
  bool from_default = false;
  YAML::Node node = value_or_default(spec, from_default);
  const std::string text =
      from_default ? std::string(spec.default_text) : (node.IsScalar() ? node.Scalar() : "");
  if (text == "true" || text == "yes" || text == "on") return true;
  if (text == "false" || text == "no" || text == "off") return false;
  fail(node, spec.key, fmt::format("expected true or false but found '{}'", text));
}

std::string BlockReader::string(const ParamSpec& spec) {
  bool from_default = false;
  YAML::Node node = value_or_default(spec, from_default);
  if (from_default) return std::string(spec.default_text);
  if (!node.IsScalar()) fail(node, spec.key, "expected a text value");
  return node.Scalar();
}

void BlockReader::finish(std::span<const ParamSpec> specs,
                         std::span<const std::string_view> extra_keys) const {
  if (!node_.IsDefined() || !node_.IsMap()) return;
  std::vector<std::pair<std::string, YAML::Node>> present;
  leaves(node_, "", present);
  std::vector<std::string> known;
  for (const auto& s : specs) known.emplace_back(s.key);
  for (const auto& k : extra_keys) known.emplace_back(k);
  for (const auto& [key, key_node] : present) {
    // A key is accounted for when it, or a map above it, or a key below it, was taken.
    bool ok = false;
    for (const auto& u : used_) {
      if (u == key || key.starts_with(u + ".") || u.starts_with(key + ".")) {
        ok = true;
        break;
      }
    }
    if (ok) continue;
    std::string best;
    std::size_t best_d = 4;
    for (const auto& k : known) {
      const std::size_t d = edit_distance(key, k);
      if (d < best_d) best_d = d, best = k;
    }
    // The keys of the same group (boundary.* for boundary.overlapp) when it has any, else all: a list a
    // reader can take in, the rest are in `beadtwin params`.
    const std::size_t dot = key.rfind('.');
    const std::string group = dot == std::string::npos ? std::string() : key.substr(0, dot + 1);
    std::string list;
    for (const auto& k : known)
      if (!group.empty() && k.starts_with(group)) list += (list.empty() ? "" : ", ") + k;
    if (list.empty())
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError(where(key_node, key), full_key(key),
                     best.empty()
                         ? fmt::format("unknown key; expected one of: {}", list)
                         : fmt::format("unknown key; did you mean '{}'? Expected one of: {}", best, list));
  }
}

}  // namespace beadtwin::scenarios
