// The `ranges:` block of a material or machine file (docs/parameters.md, ranges): the plausible values of
// the inputs that decide the fusion verdicts, keyed by the same key paths as the values they spread.
#include "scenarios/input/ranges.hpp"

#include <cmath>

#include <fmt/format.h>

namespace beadtwin::scenarios {
namespace {

std::string keys_text(std::span<const RangeKey> keys) {
  std::string out;
  for (const RangeKey& k : keys) out += (out.empty() ? "" : ", ") + std::string(k.key);
  return out;
}

const RangeKey* find_key(std::span<const RangeKey> keys, std::string_view key) {
  for (const RangeKey& k : keys)
    if (k.key == key) return &k;
  return nullptr;
}

// The entries of the block as (dotted key, node), nested maps flattened: a map that holds one of the range's
// own words (range, scale, sigma, distribution) is an entry, as is a list.
void flatten(const YAML::Node& node, const std::string& prefix,
             std::vector<std::pair<std::string, YAML::Node>>& out) {
  for (const auto& item : node) {
    const std::string key = prefix + item.first.as<std::string>();
    const YAML::Node& v = item.second;
    const bool entry = !v.IsMap() || v["range"] || v["scale"] || v["sigma"] || v["distribution"];
    if (entry)
      out.emplace_back(key, v);
    else
      flatten(v, key + ".", out);
  }
}

class RangeReader {
 public:
  RangeReader(const BlockReader& r, std::string key, const RangeKey& k)
      : r_(r), key_(std::move(key)), k_(k) {}

  InputRange read(const YAML::Node& node) const {
    InputRange out{.key = std::string(k_.key)};
    if (node.IsMap()) {
      for (const auto& item : node) {
        const std::string word = item.first.as<std::string>();
        if (word != "range" && word != "scale" && word != "sigma" && word != "distribution")
          r_.fail(item.first, key_,
                  fmt::format("unknown word '{}' in a range; expected range: [lo, hi], scale: [lo, hi], "
                              "sigma and distribution: uniform, log-uniform or normal",
                              word));
      }
      if (node["range"] && node["scale"]) r_.fail(node, key_, "give range or scale, not both");
      out.scale = static_cast<bool>(node["scale"]);
      if (const YAML::Node d = node["distribution"]) out.spread = spread(d);
    }
    // Bound once: assigning to a YAML::Node would overwrite the node it refers to.
    const YAML::Node ends = !node.IsMap() ? node : out.scale ? node["scale"] : node["range"];
    if (k_.scale_only && !out.scale)
      r_.fail(node, key_,
              fmt::format("give {}'s range as factors on its value{}: {{scale: [lo, hi]}}", k_.key, k_.why));
    const Dimension dim = out.scale ? Dimension::kDimensionless : k_.dim;
    const double value = out.scale ? 1.0 : k_.value;
    if (out.spread == Spread::kNormal) {
      const YAML::Node sigma = node["sigma"];  // a map: the distribution is one of its words
      if (!sigma || node["range"] || node["scale"])
        r_.fail(
            node, key_,
            "a normal spread is about the value: give its sigma (standard deviation) and no range or scale");
      // A temperature's sigma is a difference: kelvin, a plain number.
      out.sigma = r_.parse(sigma, dim == Dimension::kTemperature ? Dimension::kDimensionless : dim, key_);
      if (!(out.sigma > 0.0)) r_.fail(sigma, key_, fmt::format("sigma must be above 0, got {}", out.sigma));
      out.lo = out.hi = value;
      return out;
    }
    if (node.IsMap() && node["sigma"]) r_.fail(node["sigma"], key_, "sigma is for distribution: normal");
    if (!ends || !ends.IsSequence() || ends.size() != 2)
      r_.fail(ends ? ends : node, key_,
              "expected [lo, hi], or a map with range: [lo, hi] or scale: [lo, hi]");
    out.lo = r_.parse(ends[0], dim, key_);
    out.hi = r_.parse(ends[1], dim, key_);
    if (out.lo > out.hi)
      r_.fail(ends, key_, fmt::format("the range's low end {:g} is above its high end {:g}", out.lo, out.hi));
    if (out.spread == Spread::kLogUniform && !(out.lo > 0.0))
      r_.fail(ends, key_, "a log-uniform range needs a low end above 0");
    if (!(out.lo <= value && value <= out.hi)) {
      if (k_.overridden) return recentred(out);
      r_.fail(ends, key_,
              out.scale ? fmt::format("the factors [{:g}, {:g}] do not contain 1 (the value itself)", out.lo,
                                      out.hi)
                        : fmt::format("the range [{:g}, {:g}] does not contain the value {:g} ({}): widen it",
                                      out.lo, out.hi, value, k_.key));
    }
    return out;
  }

 private:
  // A range that a variant's value has left: moved to centre on the value, its width kept (a temperature's,
  // the emissivity's) or its factors about its middle (a coefficient's).
  InputRange recentred(InputRange r) const {
    const double v = k_.value;
    if (k_.dim == Dimension::kTemperature || k_.dim == Dimension::kFraction ||
        k_.dim == Dimension::kDimensionless) {
      const double half = 0.5 * (r.hi - r.lo);
      r.lo = v - half;
      r.hi = v + half;
    } else {
      const double mid = r.spread == Spread::kLogUniform ? std::sqrt(r.lo * r.hi) : 0.5 * (r.lo + r.hi);
      r.lo *= v / mid;
      r.hi *= v / mid;
    }
    return r;
  }

  Spread spread(const YAML::Node& d) const {
    const std::string text = d.IsScalar() ? d.Scalar() : "";
    if (const Spread* s = value_named<Spread>(text)) return *s;
    r_.fail(d, key_, fmt::format("unknown distribution '{}'; expected uniform, log-uniform or normal", text));
  }

  const BlockReader& r_;
  std::string key_;
  const RangeKey& k_;
};

}  // namespace

std::vector<InputRange> read_ranges(BlockReader& r, std::vector<RangeKey> keys) {
  const auto* overridden = r.overridden();
  for (RangeKey& k : keys)
    if (overridden != nullptr)
      for (const auto& [key, at] : *overridden)  // the key itself, or one of a group's (conductivity.along)
        k.overridden = k.overridden || key == r.full_key(k.key) || key.starts_with(r.full_key(k.key) + ".");
  std::vector<InputRange> out;
  const YAML::Node block = r.take("ranges");
  if (!block.IsDefined() || block.IsNull()) return out;
  if (!block.IsMap()) r.fail(block, "ranges", "expected a map of key: [lo, hi]");
  std::vector<std::pair<std::string, YAML::Node>> entries;
  flatten(block, "", entries);
  for (const auto& [key, node] : entries) {
    const std::string full = "ranges." + key;
    const RangeKey* k = find_key(keys, key);
    if (k == nullptr)
      r.fail(node, full,
             fmt::format("no range is read for '{}'; the inputs that take one: {}", key, keys_text(keys)));
    out.push_back(RangeReader(r, full, *k).read(node));
  }
  return out;
}

}  // namespace beadtwin::scenarios
