// Machine codes for the G-code reader (gcode/block_reader.hpp): "M23" as a letter and a number, the sets
// of them ReaderOptions names, matched against a block's words, a block's parameter words, and a block
// sorted by what its words mean.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gcode/block.hpp"

namespace beadtwin::gcode {

struct ReaderOptions;

// A code's number in tenths, so that M862.3 and M23 compare exactly: 8623 and 230. std::lround(value * 10)
// (halves away from zero), inline for the numbers codes have: the fraction of a double is exact.
inline int code_tenths(double value) {
  const double x = value * 10.0;
  if (!(std::abs(x) < 1e9)) return static_cast<int>(std::lround(x));
  const auto whole = static_cast<long>(x);  // towards zero
  const double fraction = x - static_cast<double>(whole);
  if (fraction >= 0.5) return static_cast<int>(whole + 1);
  if (fraction <= -0.5) return static_cast<int>(whole - 1);
  return static_cast<int>(whole);
}

// One machine code: M23 is {'M', 230}.
struct MachineCode {
  char letter = 0;
  int tenths = 0;
};

// A set of machine codes, as one ReaderOptions entry names them ("M23", "M101.1").
class CodeSet {
 public:
  CodeSet() = default;
  // Throws InputError (key `key`) for a text that is not a letter and a non-negative number.
  CodeSet(const std::vector<std::string>& codes, const std::string& key);
  bool matches(const Word& w) const;  // whether `w` is one of the codes
  bool empty() const { return codes_.empty(); }

 private:
  std::vector<MachineCode> codes_;
};

// The codes of ReaderOptions, parsed once.
struct CodeSets {
  explicit CodeSets(const ReaderOptions& o);
  // Whether the reader acts on M code `w`: a machine code of the options, M2, M30, M82, M83 or M200.
  bool acts_on(const Word& w) const;

  CodeSet melt_on, melt_off, heat_on, heat_off, roller_down, roller_up, fan_on, fan_off, nozzle_temp, prime,
      reverse_on, reverse_off, ignored;
};

// The parameter words of one block, each taken by the code that uses it; the rest are reported unused.
// Letters A to Z are found through a table, others by search.
class Params {
 public:
  // Adds a parameter word; a letter already there is kept as repeated (reported unused).
  void add(const Word& w) {
    if (find(w.letter)) {
      repeated_.push_back(w);
      return;
    }
    if (const int k = slot(w.letter); k >= 0) index_[static_cast<std::size_t>(k)] = entries_.size() + 1;
    entries_.push_back({w, false});
  }
  // The value of `letter`, marked used; nullopt when the block has none.
  std::optional<double> take(char letter) {
    Entry* e = find(letter);
    if (!e) return std::nullopt;
    e->used = true;
    return e->word.value;
  }
  bool has(char letter) const { return find(letter) != nullptr; }
  int column(char letter) const {
    const Entry* e = find(letter);
    return e ? e->word.column : 0;
  }
  void clear() {
    for (const Entry& e : entries_)
      if (const int k = slot(e.word.letter); k >= 0) index_[static_cast<std::size_t>(k)] = 0;
    entries_.clear();
    repeated_.clear();
  }
  // Marks every word used (a code that consumes whatever parameters it has).
  void take_all() {
    for (Entry& e : entries_) e.used = true;
  }
  // The words no code took, repeated letters first.
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
  static int slot(char letter) { return letter >= 'A' && letter <= 'Z' ? letter - 'A' : -1; }
  const Entry* find(char letter) const {
    if (const int k = slot(letter); k >= 0) {
      const std::size_t at = index_[static_cast<std::size_t>(k)];
      return at ? &entries_[at - 1] : nullptr;
    }
    for (const Entry& e : entries_)
      if (e.word.letter == letter) return &e;
    return nullptr;
  }
  Entry* find(char letter) { return const_cast<Entry*>(std::as_const(*this).find(letter)); }

  std::vector<Entry> entries_;
  std::array<std::size_t, 26> index_{};  // 1 + the entry of each letter A-Z; 0: none
  std::vector<Word> repeated_;
};

// One block sorted for the reader: its G and M codes by meaning, its parameters. The reader keeps one and
// clears it for each block, so that its vectors' memory is reused.
struct SortedBlock {
  std::vector<Word> modal_g;   // G17-19, G20/21, G90/91
  std::optional<Word> motion;  // G0-G3
  std::optional<Word> dwell, set_position, home;
  std::vector<Word> unhandled;  // codes ignored or unknown: their parameters are theirs
  std::vector<Word> unknown;
  std::vector<Word> m;       // M codes the reader acts on
  std::optional<Word> tool;  // a T word
  Params params;

  void clear() {
    for (std::vector<Word>* v : {&modal_g, &unhandled, &unknown, &m}) v->clear();
    motion = dwell = set_position = home = tool = std::nullopt;
    params.clear();
  }
};

}  // namespace beadtwin::gcode
