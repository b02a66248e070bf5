// Reading YAML blocks through the parameter declarations (core/param.hpp), with every problem reported as
// an InputError that names the file, line, column and key : unknown keys, missing required
// keys, wrong units, values of the wrong form and values out of range.
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
#include "core/param.hpp"

namespace beadtwin::scenarios {

// Where a block of YAML came from, and the default units for bare numbers declared there (`units:`).
struct YamlSource {
  std::string file;
  std::map<Dimension, std::string> default_units;
};

// Parses a `units:` block ({length: in, temperature: C, ...}) into default units per dimension.
std::map<Dimension, std::string> read_units_block(const YAML::Node& node, const std::string& file);

// A path that exists but is no regular file (a named pipe, a device, a folder): reading it could wait for
// ever or mean nothing, so it is refused rather than opened.
bool is_special_file(const std::filesystem::path& path);

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

  // Reads every declared key that has a member into `block`: the value given, else the declared default;
  // a required key that is absent is an error (naming a likely misspelling). A derived key that is absent
  // leaves its member as it is, for the block's own code. Returns the keys the file gives.
  template <class B>
  std::set<std::string_view> read(std::span<const Param<B>> params, B& block);

  // The value of `node` as the declaration `info` says it is written (`shape`, a point's `point_size`, the
  // words of a choice), checked against its range; fails naming the key.
  ParamValue value(const YAML::Node& node, const ParamInfo& info, ParamShape shape, std::size_t point_size,
                   std::span<const std::string_view> spellings) const;
  // The declaration's default, read as `value` reads a file's (without the file's default units).
  ParamValue default_value(const ParamInfo& info, ParamShape shape, std::size_t point_size,
                           std::span<const std::string_view> spellings) const;
  // Fails where a group of dotted keys ("outline" of outline.points) is given as something other than a
  // map, unless the group is itself one of `keys` (fill: none).
  void check_groups(std::span<const std::string_view> keys) const;
  // Fails for a required key that is absent, pointing at a present key that looks like a misspelling of it.
  [[noreturn]] void missing(const ParamInfo& info) const;

  // Parses a scalar node as a quantity of `dim`, with this block's default units; `key` for messages.
  double parse(const YAML::Node& node, Dimension dim, const std::string& key) const;
  // `text` (the scalar of `node`) as a whole number; fails naming `key` when it is not one.
  long whole_number(const std::string& text, const YAML::Node& node, std::string_view key) const;
  // Checks a value against a declaration's range.
  void check_range(const ParamInfo& info, double value, const YAML::Node& node) const;

  // Every key present but never taken is an error ("unknown key 'x'; did you mean ...? Expected one of:
  // ..."), naming the keys of `tables` (declaration tables of this block) as the known ones.
  template <class... B>
  void finish(std::span<const Param<B>>... tables) const {
    std::vector<std::string_view> known;
    (add_keys(known, tables), ...);
    finish_known(known);
  }
  void finish_known(std::span<const std::string_view> known) const;

  std::string full_key(std::string_view key) const;
  SourceLocation where(const YAML::Node& node, std::string_view key = {}) const;
  [[noreturn]] void fail(const YAML::Node& node, std::string_view key, const std::string& message) const;
  const YamlSource& source() const { return *source_; }
  // For a reader of a block nested in this one (an entry of a list).
  std::shared_ptr<const YamlSource> shared_source() const { return source_; }
  const std::map<std::string, SourceLocation>* overridden() const { return overridden_; }

 private:
  YAML::Node find(std::string_view dotted) const;
  template <class B>
  static void add_keys(std::vector<std::string_view>& keys, std::span<const Param<B>> table) {
    for (const Param<B>& p : table) keys.push_back(p.key);
  }
  // A scalar's text, or a failure naming `info` when the node is not one.
  const std::string& scalar(const YAML::Node& node, const ParamInfo& info, std::string_view expected) const;
  ParamValue point(const YAML::Node& node, const ParamInfo& info, std::size_t size) const;
  ParamValue polygon(const YAML::Node& node, const ParamInfo& info) const;
  ParamValue table(const YAML::Node& node, const ParamInfo& info) const;
  ParamValue integers(const YAML::Node& node, const ParamInfo& info) const;

  YAML::Node node_;
  std::string prefix_;
  std::shared_ptr<const YamlSource> source_;
  const std::map<std::string, SourceLocation>* overridden_;
  std::set<std::string, std::less<>> used_;
};

template <class B>
std::set<std::string_view> BlockReader::read(std::span<const Param<B>> params, B& block) {
  std::vector<std::string_view> keys;
  for (const Param<B>& p : params) keys.push_back(p.key);
  check_groups(keys);
  std::set<std::string_view> given;
  for (const Param<B>& p : params) {
    if (!p.member) continue;
    const std::vector<std::string_view> spellings = p.spellings();
    const YAML::Node node = take(p.key);
    if (node.IsDefined() && !node.IsNull()) {
      p.set(block, value(node, p, p.shape(), p.member.point_size(), spellings));
      given.insert(p.key);
    } else if (!p.default_text.empty()) {
      p.set(block, default_value(p, p.shape(), p.member.point_size(), spellings));
    } else if (p.required()) {
      missing(p);
    }
  }
  return given;
}

}  // namespace beadtwin::scenarios
