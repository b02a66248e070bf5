#include "scenarios/input/yaml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace beadtwin::scenarios {
namespace {

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

bool is_special_file(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec);
}

// Scenario, machine, material and gate files are text people write: a few kB. One far larger is not one of
// them (a mesh or a program named by mistake), and yaml-cpp takes some fifty times a file's size to hold it.
constexpr std::uintmax_t kMaxTextFileBytes = 16u << 20;

std::string read_text_file(const std::filesystem::path& path, const SourceLocation& from,
                           const std::string& key) {
  if (is_special_file(path))
    throw InputError(from, key, fmt::format("'{}' is not a regular file", path.string()));
  std::error_code ec;
  if (const std::uintmax_t bytes = std::filesystem::file_size(path, ec); !ec && bytes > kMaxTextFileBytes)
    throw InputError(
        from, key,
        fmt::format("'{}' is {:.1f} MB, too large for a YAML settings file (at most {} MB); is it "
                    "the right file?",
                    path.string(), static_cast<double>(bytes) / (1 << 20), kMaxTextFileBytes >> 20));
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(from, key, fmt::format("cannot open '{}'", path.string()));
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

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
  // Each level may hold the rest of the path as one key ("camera.position: [...]") or as nested maps
  // ("camera: {position: [...]}").
  YAML::Node cur = node_;
  std::string_view rest = dotted;
  while (true) {
    if (!cur.IsDefined() || !cur.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& level = cur;
    if (const YAML::Node whole = level[std::string(rest)]; whole.IsDefined()) return whole;
    const std::size_t dot = rest.find('.');
    if (dot == std::string_view::npos) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node next = level[std::string(rest.substr(0, dot))];
    if (!next.IsDefined()) return YAML::Node(YAML::NodeType::Undefined);
    cur.reset(next);
    rest.remove_prefix(dot + 1);
  }
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

void BlockReader::check_range(const ParamInfo& info, double value, const YAML::Node& node) const {
  if (!info.range.contains(value)) fail(node, info.key, out_of_range_text(info, value));
}

void BlockReader::missing(const ParamInfo& info) const {
  // A misspelling of the key is the likeliest reason: point at it.
  if (node_.IsDefined() && node_.IsMap()) {
    std::vector<std::pair<std::string, YAML::Node>> present;
    leaves(node_, "", present);
    for (const auto& [key, key_node] : present) {
      if (key != info.key && edit_distance(key, info.key) <= 2)
        throw InputError(
            where(key_node, key), full_key(key),
            fmt::format("unknown key; did you mean '{}'? (required: {})", info.key, info.meaning));
    }
  }
  fail(node_, info.key, fmt::format("required key is missing ({})", info.meaning));
}

void BlockReader::check_groups(std::span<const std::string_view> keys) const {
  for (const std::string_view key : keys) {
    const std::size_t dot = key.rfind('.');
    if (dot == std::string_view::npos) continue;
    const std::string_view group = key.substr(0, dot);
    if (std::find(keys.begin(), keys.end(), group) != keys.end()) continue;
    const YAML::Node node = find(group);
    if (!node.IsDefined() || node.IsNull() || node.IsMap()) continue;
    std::string members;
    for (const std::string_view k : keys)
      if (k.starts_with(std::string(group) + "."))
        members += (members.empty() ? "" : ", ") + std::string(k.substr(dot + 1));
    fail(node, group, fmt::format("expected a map of its keys ({})", members));
  }
}

const std::string& BlockReader::scalar(const YAML::Node& node, const ParamInfo& info,
                                       std::string_view expected) const {
  if (!node.IsScalar()) fail(node, info.key, fmt::format("expected {}", expected));
  return node.Scalar();
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

namespace {

// "lengths", "numbers", "temperatures": a point's coordinates in a message.
std::string plural(Dimension dim) {
  return dim == Dimension::kDimensionless || dim == Dimension::kFraction
             ? std::string("numbers")
             : std::string(dimension_name(dim)) + "s";
}

std::string_view coordinates(std::size_t size) {
  return size == 3 ? "[x, y, z]" : "[x, y]";
}

}  // namespace

ParamValue BlockReader::point(const YAML::Node& node, const ParamInfo& info, std::size_t size) const {
  const std::string key(info.key);
  if (!node.IsSequence() || node.size() != size)
    fail(node, key,
         fmt::format("expected {} {} {}", size == 3 ? "three" : "two", plural(info.dim), coordinates(size)));
  ParamValue::List out;
  bool zero = true;
  for (std::size_t i = 0; i < size; ++i) {
    const double x = parse(node[i], info.dim, key);
    check_range(info, x, node[i]);
    zero = zero && x == 0.0;
    out.emplace_back(x);
  }
  if (info.nonzero && zero)
    fail(node, key, fmt::format("a direction cannot be {}", size == 3 ? "[0, 0, 0]" : "[0, 0]"));
  return out;
}

ParamValue BlockReader::polygon(const YAML::Node& node, const ParamInfo& info) const {
  const std::string key(info.key);
  if (!node.IsSequence() || node.size() < info.min_points)
    fail(node, key, fmt::format("expected at least {} points [[x, y], ...]", info.min_points));
  ParamValue::List out;
  for (const YAML::Node& p : node) {
    if (!p.IsSequence() || p.size() != 2) fail(p, key, "expected a point [x, y]");
    const double x = parse(p[0], info.dim, key), y = parse(p[1], info.dim, key);
    if (!info.range.contains(x) || !info.range.contains(y)) {
      // Beyond the range is a mistake of units: a part is at most this far from the origin.
      fail(p, key,
           fmt::format(
               "the point ({:.6g}, {:.6g}) {} is more than {:g} m from the origin; are the units right?", x,
               y, internal_unit(info.dim), info.range.max / 1000));
    }
    out.emplace_back(ParamValue::List{x, y});
  }
  return out;
}

ParamValue BlockReader::table(const YAML::Node& node, const ParamInfo& info) const {
  const std::string key(info.key);
  const std::string a(dimension_name(info.column_dim)), b(dimension_name(info.dim));
  if (!node.IsSequence() || node.size() == 0)
    fail(node, key, fmt::format("expected a list of [{}, {}] points", a, b));
  ParamValue::List out;
  double last = -std::numeric_limits<double>::infinity();
  for (const YAML::Node& row : node) {
    if (!row.IsSequence() || row.size() != 2) fail(row, key, fmt::format("expected a point [{}, {}]", a, b));
    const double x = parse(row[0], info.column_dim, key), y = parse(row[1], info.dim, key);
    check_range(info, y, row[1]);
    if (!(x > last)) fail(row, key, fmt::format("the {}s must increase from one point to the next", a));
    last = x;
    out.emplace_back(ParamValue::List{x, y});
  }
  return out;
}

ParamValue BlockReader::integers(const YAML::Node& node, const ParamInfo& info) const {
  if (!node.IsSequence()) fail(node, info.key, "expected a list of whole numbers such as [0, 14, 29]");
  ParamValue::List out;
  for (const YAML::Node& item : node) {
    const long v = whole_number(item.IsScalar() ? item.Scalar() : "", item, info.key);
    check_range(info, static_cast<double>(v), item);
    if (std::find(out.begin(), out.end(), ParamValue(v)) != out.end())
      fail(item, info.key, fmt::format("{} is in the list twice", v));
    out.emplace_back(v);
  }
  return out;
}

ParamValue BlockReader::value(const YAML::Node& node, const ParamInfo& info, ParamShape shape,
                              std::size_t point_size, std::span<const std::string_view> spellings) const {
  const std::string key(info.key);
  switch (shape) {
    case ParamShape::kNumber: {
      const double v = parse(node, info.dim, key);
      check_range(info, v, node);
      return v;
    }
    case ParamShape::kInteger: {
      const long v = whole_number(node.IsScalar() ? node.Scalar() : "", node, key);
      check_range(info, static_cast<double>(v), node);
      return v;
    }
    case ParamShape::kFlag:
      if (spellings.empty()) {
        const std::string text = node.IsScalar() ? node.Scalar() : "";
        if (text == "true" || text == "yes" || text == "on") return true;
        if (text == "false" || text == "no" || text == "off") return false;
        fail(node, key, fmt::format("expected true or false but found '{}'", text));
      }
      [[fallthrough]];
    case ParamShape::kText:
    case ParamShape::kChoice: {
      const std::string& text = scalar(node, info, spellings.empty() ? "a text value" : "one word");
      if (!spellings.empty() && std::find(spellings.begin(), spellings.end(), text) == spellings.end())
        fail(node, key,
             fmt::format("expected one of {} but found '{}'", spellings_text(spellings, ", "), text));
      return text;
    }
    case ParamShape::kPoint:
      return point(node, info, point_size);
    case ParamShape::kPolygon:
      return polygon(node, info);
    case ParamShape::kPolygons: {
      // One polygon [[x, y], ...], or a list of them [[[x, y], ...], ...].
      const bool many = node.IsSequence() && node.size() > 0 && node[0].IsSequence() && node[0].size() > 0 &&
                        node[0][0].IsSequence();
      if (!many) return ParamValue::List{polygon(node, info)};
      ParamValue::List out;
      for (const YAML::Node& one : node) out.push_back(polygon(one, info));
      return out;
    }
    case ParamShape::kTable:
      return table(node, info);
    case ParamShape::kIntegers:
      return integers(node, info);
    case ParamShape::kNone:
      break;
  }
  throw InternalError(fmt::format("parameter '{}' has no member to read into", info.key));
}

ParamValue BlockReader::default_value(const ParamInfo& info, ParamShape shape, std::size_t point_size,
                                      std::span<const std::string_view> spellings) const {
  // The declaration's text, as a file of its own: no default units, messages naming the declaration.
  static const auto kDeclared = std::make_shared<const YamlSource>(YamlSource{"<declared default>", {}});
  const BlockReader declared(YAML::Node(YAML::NodeType::Map), full_key(""), kDeclared);
  // A list is YAML; anything else is one scalar as written ("-" is a text, not a YAML list).
  const std::string text(info.default_text);
  const YAML::Node node = text.starts_with('[') ? YAML::Load(text) : YAML::Node(text);
  return declared.value(node, info, shape, point_size, spellings);
}

void BlockReader::finish_known(std::span<const std::string_view> known_keys) const {
  if (!node_.IsDefined() || !node_.IsMap()) return;
  std::vector<std::pair<std::string, YAML::Node>> present;
  leaves(node_, "", present);
  const std::vector<std::string> known(known_keys.begin(), known_keys.end());
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
