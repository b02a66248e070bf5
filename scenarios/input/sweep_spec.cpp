// What a sweep runs (scenarios/sweep.hpp): its axes from the command line, its combinations from a file,
// and the points they expand to. Input reading only, so it lives with the scenario readers.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "scenarios/input/metrics.hpp"
#include "scenarios/input/sweep_spec.hpp"
#include "scenarios/input/yaml_reader.hpp"

namespace beadtwin::scenarios {
namespace {

const SourceLocation kCommandLine{"command line", 0, 0};

std::string trimmed(std::string s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// `text` split at the commas outside brackets, braces and quotes.
std::vector<std::string> split_values(const std::string& text) {
  std::vector<std::string> out;
  std::string piece;
  int depth = 0;
  char quote = 0;
  for (const char c : text) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    } else if (c == ',' && depth == 0) {
      out.push_back(trimmed(piece));
      piece.clear();
      continue;
    }
    piece += c;
  }
  out.push_back(trimmed(piece));
  return out;
}

// A YAML value as the text --set takes: a scalar as written, a list or map in flow style ([0, 5]).
std::string value_text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter e;
  e << YAML::Flow << node;
  return e.c_str();
}

std::vector<std::vector<Setting>> read_combinations(const YAML::Node& root, const std::string& file);

}  // namespace

SweepAxis parse_sweep_axis(const std::string& text) {
  const Setting s = parse_setting(text);
  SweepAxis axis{s.key, split_values(s.value)};
  for (std::size_t i = 0; i < axis.values.size(); ++i)
    if (axis.values[i].empty())
      throw InputError(kCommandLine, "--set",
                       fmt::format("'{}': value {} of {} is empty; expected KEY=V1,V2,... such as "
                                   "sections.walls.bead_width=18mm,20mm,22mm",
                                   text, i + 1, axis.values.size()));
  return axis;
}

std::vector<std::vector<Setting>> load_sweep_combinations(const std::filesystem::path& path) {
  const std::string file = path.string();
  return parse_sweep_combinations(read_text_file(path, {file, 0, 0}, "--combinations"), file);
}

std::vector<std::vector<Setting>> parse_sweep_combinations(const std::string& text, const std::string& file) {
  try {
    return read_combinations(parse_yaml(text, file), file);
  } catch (const YAML::Exception& e) {
    // Every node is checked for its kind before it is read; this is the last line of defence (fuzzed).
    throw InputError({file, e.mark.line + 1, e.mark.column + 1}, {},
                     fmt::format("unexpected YAML structure: {}", e.msg));
  }
}

namespace {

std::vector<std::vector<Setting>> read_combinations(const YAML::Node& root, const std::string& file) {
  const YAML::Node list = root.IsMap() && root["combinations"] ? root["combinations"] : root;
  constexpr const char* kExpected =
      "expected a list of combinations, each a map of settings such as "
      "'- {sections.walls.bead_width: 20 mm, sections.walls.speed: 1.2 in/s}'";
  if (!list.IsSequence() || list.size() == 0)
    throw InputError(location_of(list.IsDefined() ? list : root, file), "combinations", kExpected);
  std::vector<std::vector<Setting>> rows;
  for (const YAML::Node& row : list) {
    if (!row.IsMap() || row.size() == 0) throw InputError(location_of(row, file), "combinations", kExpected);
    std::vector<Setting> settings;
    std::set<std::string> keys;
    for (auto it = row.begin(); it != row.end(); ++it) {
      if (!it->first.IsScalar() || it->first.Scalar().empty())
        throw InputError(location_of(it->first, file), "combinations", "a setting's key must be a key path");
      const std::string key = it->first.Scalar();
      if (!keys.insert(key).second)
        throw InputError(location_of(it->first, file), key, "set twice in one combination");
      if (!it->second.IsDefined() || it->second.IsNull())
        throw InputError(location_of(it->first, file), key, "has no value");
      settings.push_back({key, value_text(it->second)});
    }
    rows.push_back(std::move(settings));
  }
  return rows;
}

}  // namespace

std::vector<SweepPoint> expand_sweep(const std::vector<SweepAxis>& axes,
                                     const std::vector<std::vector<Setting>>& rows) {
  const std::vector<std::vector<Setting>> base_rows =
      rows.empty() ? std::vector<std::vector<Setting>>(1) : rows;
  double count = static_cast<double>(base_rows.size());
  for (const SweepAxis& a : axes) count *= static_cast<double>(a.values.size());
  if (count > static_cast<double>(kMaxSweepVariants))
    throw InputError(kCommandLine, "--set",
                     fmt::format("the sweep would run {:.0f} variants, more than {}: split it into smaller "
                                 "sweeps or list the combinations wanted in a file (--combinations)",
                                 count, kMaxSweepVariants));
  const auto total = static_cast<std::size_t>(count);
  const int digits = std::max(3, static_cast<int>(std::to_string(total).size()));
  std::vector<SweepPoint> points;
  points.reserve(total);
  for (const std::vector<Setting>& row : base_rows) {
    // The factorial as a mixed-radix counter, the last axis turning fastest.
    std::vector<std::size_t> at(axes.size(), 0);
    for (bool more = true; more;) {
      SweepPoint p;
      p.name = fmt::format("v{:0{}}", points.size() + 1, digits);
      p.settings = row;
      for (std::size_t a = 0; a < axes.size(); ++a) {
        const auto same = [&](const Setting& s) { return s.key == axes[a].key; };
        if (std::any_of(p.settings.begin(), p.settings.end(), same))
          throw InputError(kCommandLine, axes[a].key,
                           "is set twice in one variant (by two --set options, or by --set and the "
                           "combinations file); give it once");
        p.settings.push_back({axes[a].key, axes[a].values[at[a]]});
      }
      points.push_back(std::move(p));
      more = false;
      for (std::size_t a = axes.size(); a-- > 0;) {
        if (++at[a] < axes[a].values.size()) {
          more = true;
          break;
        }
        at[a] = 0;
      }
    }
  }
  return points;
}

Objective parse_objective(const std::string& text, const std::string& option) {
  Objective o{trimmed(text), false};
  if (const auto colon = o.metric.rfind(':'); colon != std::string::npos) {
    const std::string sense = o.metric.substr(colon + 1);
    if (sense != "min" && sense != "max")
      throw InputError(kCommandLine, option,
                       fmt::format("'{}': after the metric expected :min or :max, got ':{}'", text, sense));
    o.maximise = sense == "max";
    o.metric = trimmed(o.metric.substr(0, colon));
  }
  if (!is_gate_metric(o.metric)) throw InputError(kCommandLine, option, unknown_metric_message(o.metric));
  return o;
}

}  // namespace beadtwin::scenarios
