// Gates: the pass/fail conditions a run is judged by, as written in a scenario, a gates file or on the
// command line.
#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "scenarios/input/metrics.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/input/scenario_blocks.hpp"

namespace beadtwin::scenarios {

Gate parse_gate_text(const std::string& expr, const SourceLocation& at) {
  Gate g;
  g.expr = expr;
  g.where = at;
  static const std::pair<std::string_view, GateOp> kOps[] = {
      {"<=", GateOp::kLessEqual}, {">=", GateOp::kGreaterEqual}, {"==", GateOp::kEqual},
      {"!=", GateOp::kNotEqual},  {"<", GateOp::kLess},          {">", GateOp::kGreater}};
  std::size_t pos = std::string::npos, len = 0;
  for (const auto& [text, op] : kOps) {
    const std::size_t p = g.expr.find(text);
    if (p != std::string::npos) {
      pos = p;
      len = text.size();
      g.op = op;
      break;
    }
  }
  if (pos == std::string::npos)
    throw InputError(at, "gates", fmt::format("'{}' has no comparison (<, <=, >, >=, ==, !=)", g.expr));
  auto trim = [](std::string s) {
    s.erase(0, s.find_first_not_of(" \t"));
    s.erase(s.find_last_not_of(" \t") + 1);
    return s;
  };
  g.metric = trim(g.expr.substr(0, pos));
  const std::string rhs = trim(g.expr.substr(pos + len));
  if (!is_gate_metric(g.metric)) throw InputError(at, "gates", unknown_metric_message(g.metric));
  const auto number = [&](const std::string& text) {
    try {
      return parse_quantity(trim(text), Dimension::kFraction);
    } catch (const QuantityError& e) {
      throw InputError(
          at, "gates",
          fmt::format("'{}': the right-hand side must be a number, or baseline, baseline * number or "
                      "baseline + number: {}",
                      g.expr, e.what()));
    }
  };
  if (rhs.rfind("baseline", 0) == 0) {
    // Relative to the baseline variant: baseline, baseline * f, baseline + d, baseline - d.
    g.relative = true;
    const std::string rest = trim(rhs.substr(std::string_view("baseline").size()));
    if (!rest.empty()) {
      const char op = rest.front();
      const double v = number(rest.substr(1));
      if (op == '*')
        g.factor = v;
      else if (op == '+')
        g.offset = v;
      else if (op == '-')
        g.offset = -v;
      else
        throw InputError(at, "gates",
                         fmt::format("'{}': after baseline expected * number, + number or - number", g.expr));
    }
  } else {
    g.threshold = number(rhs);
  }
  return g;
}

std::vector<Gate> read_gates(const YAML::Node& list, const std::string& file) {
  if (!list.IsSequence())
    throw InputError(location_of(list, file), "gates",
                     "expected a list of gates such as '- porosity < 0.03' (or a scenario with gates:)");
  std::vector<Gate> out;
  for (const YAML::Node& g : list) {
    const SourceLocation at = location_of(g, file);
    if (!g.IsScalar()) throw InputError(at, "gates", "expected a gate such as 'porosity < 0.03'");
    out.push_back(parse_gate_text(g.Scalar(), at));
  }
  return out;
}

std::vector<Gate> load_gates(const std::filesystem::path& path) {
  const std::string file = path.string();
  const YAML::Node root = parse_yaml(read_text_file(path, {file, 0, 0}, "--gates"), file);
  const YAML::Node list = root.IsMap() ? root["gates"] : root;
  if (!list)
    throw InputError(location_of(root, file), "gates",
                     "expected a list of gates such as '- porosity < 0.03' (or a scenario with gates:)");
  return read_gates(list, file);
}

void check_gate_sections(const Scenario& sc) {
  // A program's sections are known once it is read: its gates are judged then.
  for (const Variant& v : sc.variants)
    if (v.program) return;
  for (const Gate& g : sc.gates) {
    const std::optional<std::string> section = gate_metric_section(g.metric);
    if (!section) continue;
    std::vector<std::string> names;
    for (const Variant& v : sc.variants)
      for (const slicer::SectionParams& s : v.sections)
        if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
    if (std::find(names.begin(), names.end(), *section) != names.end()) continue;
    throw InputError(g.where, "gates",
                     fmt::format("'{}' names section '{}', which no variant has; the sections are: {}",
                                 g.expr, *section, fmt::join(names, ", ")));
  }
}

}  // namespace beadtwin::scenarios
