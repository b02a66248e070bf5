// Machine codes for the G-code reader (slicer/gcode_reader.hpp): "M23" as a letter and a number, the sets
// of them ReaderOptions names, matched against a block's words, and a block's parameter words.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "slicer/gcode_block.hpp"

namespace beadtwin::slicer {

struct ReaderOptions;

// A code's number in tenths, so that M862.3 and M23 compare exactly: 8623 and 230.
inline int code_tenths(double value) {
  return static_cast<int>(std::lround(value * 10.0));
}

struct MachineCode {
  char letter = 0;
  int tenths = 0;
};

class CodeSet {
 public:
  CodeSet() = default;
  // Throws InputError (key `key`) for a text that is not a letter and a non-negative number.
  CodeSet(const std::vector<std::string>& codes, const std::string& key);
  bool matches(const Word& w) const;
  bool empty() const { return codes_.empty(); }

 private:
  std::vector<MachineCode> codes_;
};

// The codes of ReaderOptions, parsed once.
struct CodeSets {
  explicit CodeSets(const ReaderOptions& o);
  // Whether the reader acts on M code `w`: a machine code of the options, M2, M30, M82, M83 or M200.
  bool acts_on(const Word& w) const;

  CodeSet melt_on, melt_off, heat_on, heat_off, roller_down, roller_up, prime, reverse_on, reverse_off,
      ignored;
};

// The parameter words of one block, each taken by the code that uses it; the rest are reported unused.
class Params {
 public:
  void add(const Word& w) {
    for (const Entry& e : entries_)
      if (e.word.letter == w.letter) {
        repeated_.push_back(w);
        return;
      }
    entries_.push_back({w, false});
  }
  std::optional<double> take(char letter) {
    for (Entry& e : entries_)
      if (e.word.letter == letter) {
        e.used = true;
        return e.word.value;
      }
    return std::nullopt;
  }
  bool has(char letter) const {
    return std::any_of(entries_.begin(), entries_.end(),
                       [&](const Entry& e) { return e.word.letter == letter; });
  }
  int column(char letter) const {
    for (const Entry& e : entries_)
      if (e.word.letter == letter) return e.word.column;
    return 0;
  }
  void take_all() {
    for (Entry& e : entries_) e.used = true;
  }
  std::vector<Word> unused() const {
    std::vector<Word> out = repeated_;
    for (const Entry& e : entries_)
      if (!e.used) out.push_back(e.word);
    return out;
  }

 private:
  struct Entry {
    Word word;
    bool used;
  };
  std::vector<Entry> entries_;
  std::vector<Word> repeated_;
};

}  // namespace beadtwin::slicer
