// Reading YAML blocks through the parameter tables, with every problem reported as an InputError that
// names the file, line, column and key (STYLE.md rule 6): unknown keys, missing required keys, wrong units
// and values out of range.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>

#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "scenarios/params.hpp"

namespace beadtwin::scenarios {

// Where a block of YAML came from, and the default units for bare numbers declared there (`units:`).
struct YamlSource {
  std::string file;
  std::map<Dimension, std::string> default_units;
};

// Parses a `units:` block ({length: in, temperature: C, ...}) into default units per dimension.
std::map<Dimension, std::string> read_units_block(const YAML::Node& node, const std::string& file);

// A YAML settings file's text (a scenario, machine, material, gates or sweep combinations file): refuses a
// path that is no regular file and a file over 16 MB (not one people write), naming `from` and `key`.
std::string read_text_file(const std::filesystem::path& path, const SourceLocation& from,
                           const std::string& key);

// Parses YAML text; a syntax error becomes an InputError at its line and column.
YAML::Node parse_yaml(const std::string& text, const std::string& file);

SourceLocation location_of(const YAML::Node& node, const std::string& file);

class BlockReader {
 public:
  // `prefix` is the block's path for messages ("sections.walls", "machine").
  // `overridden` maps full key paths set by a variant to the source that set them.
  BlockReader(YAML::Node node, std::string prefix, std::shared_ptr<const YamlSource> source,
              const std::map<std::string, SourceLocation>* overridden = nullptr);

  // The node at a dotted key ("boundary.passes"), or an undefined node when absent. Marks it used.
  YAML::Node take(std::string_view dotted);
  bool has(std::string_view dotted) const;

  double quantity(const ParamSpec& spec);
  std::optional<double> optional_quantity(const ParamSpec& spec);
  int integer(const ParamSpec& spec);
  bool boolean(const ParamSpec& spec);
  std::string string(const ParamSpec& spec);

  // Parses a scalar node as a quantity of `dim`, with this block's default units; `key` for messages.
  double parse(const YAML::Node& node, Dimension dim, const std::string& key) const;
  // `text` (the scalar of `node`) as a whole number; fails naming `key` when it is not one.
  long whole_number(const std::string& text, const YAML::Node& node, std::string_view key) const;
  // Checks a value against a spec's range.
  void check_range(const ParamSpec& spec, double value, const YAML::Node& node) const;

  // Every key present but never taken is an error ("unknown key 'x'; expected one of: ...").
  void finish(std::span<const ParamSpec> specs, std::span<const std::string_view> extra_keys = {}) const;

  std::string full_key(std::string_view key) const;
  SourceLocation where(const YAML::Node& node, std::string_view key = {}) const;
  [[noreturn]] void fail(const YAML::Node& node, std::string_view key, const std::string& message) const;
  const YamlSource& source() const { return *source_; }
  // For a reader of a block nested in this one (an entry of a list).
  std::shared_ptr<const YamlSource> shared_source() const { return source_; }
  const std::map<std::string, SourceLocation>* overridden() const { return overridden_; }

 private:
  YAML::Node find(std::string_view dotted) const;
  YAML::Node value_or_default(const ParamSpec& spec, bool& from_default);

  YAML::Node node_;
  std::string prefix_;
  std::shared_ptr<const YamlSource> source_;
  const std::map<std::string, SourceLocation>* overridden_;
  std::set<std::string, std::less<>> used_;
};

}  // namespace beadtwin::scenarios
