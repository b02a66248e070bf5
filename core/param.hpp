// Parameters declared once. Each parameter a user can set is one declaration: its key,
// the typed struct member it sets, its dimension (so its unit), its default as a user writes it, its range,
// its meaning and the source it comes from. Reading a file, defaults, range checks, unknown-key errors,
// `beadtwin params`, docs/parameters.md and the report's parameter list all go through the declarations,
// so a parameter is added in one place plus the code that uses it. In the manner of PrusaSlicer's
// PrintConfig: one definition per option, bound to a typed config class.
//
// A table of declarations for a struct `Block`:
//
//   using S = SectionParams;
//   const Param<S> kSection[] = {
//       {{.key = "boundary.passes", .default_text = "1", .range = {0, 50},
//         .meaning = "number of boundary beads along each contour", .source = "patent (49)"},
//        BT_MEMBER(S, boundary.passes)},
//       ...};
//
// The member's C++ type says how the value is written (a number of the declared dimension, a whole number,
// true/false, text, one of an enumeration's spellings, a point, a polygon, a table of pairs, a list of
// whole numbers). A declaration without a member is read by its block's own code (a value of several
// forms, such as Z limits given as [lower, upper] or "part"); it is still declared here, for the docs and
// for the unknown-key check.
//
// This header knows nothing of file formats: readers turn what they read into a ParamValue (in internal
// units) and hand it to Param::set; reports and docs take ParamValue from Param::get.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "core/enum_names.hpp"
#include "core/error.hpp"
#include "core/units.hpp"

namespace beadtwin {

// A value as a reader hands it over or a report prints it, in internal units: nothing (an optional value
// not set), a number, a whole number, true/false, text (an enumeration by its spelling), or a list of
// values (a point, a polygon, a table's rows).
struct ParamValue {
  using List = std::vector<ParamValue>;
  std::variant<std::monostate, double, long, bool, std::string, List> value;

  ParamValue() = default;
  ParamValue(double v) : value(v) {}
  ParamValue(long v) : value(v) {}
  ParamValue(int v) : value(static_cast<long>(v)) {}
  ParamValue(bool v) : value(v) {}
  ParamValue(std::string v) : value(std::move(v)) {}
  ParamValue(std::string_view v) : value(std::string(v)) {}
  ParamValue(const char* v) : value(std::string(v)) {}
  ParamValue(List v) : value(std::move(v)) {}

  bool empty() const { return std::holds_alternative<std::monostate>(value); }
  // The value as the type asked for; throws InternalError when it holds another (a reader's defect).
  double number() const;  // a number, or a whole number as one
  long integer() const;
  bool flag() const;
  const std::string& text() const;
  const List& list() const;

  friend bool operator==(const ParamValue&, const ParamValue&) = default;
};

// How a parameter is written, from the C++ type of the member it sets.
enum class ParamShape : std::uint8_t {
  kNone,      // no member: the block's own code reads it
  kNumber,    // double: a quantity of the declared dimension
  kInteger,   // int or long: a whole number
  kFlag,      // bool: true or false
  kText,      // std::string
  kChoice,    // an enumeration with declared spellings (core/enum_names.hpp)
  kPoint,     // Eigen vector: [x, y] or [x, y, z], each a quantity of the declared dimension
  kPolygon,   // std::vector<Eigen::Vector2d>: [[x, y], ...]
  kPolygons,  // std::vector<std::vector<Eigen::Vector2d>>: one polygon [[x, y], ...] or a list of them
  kTable,     // std::vector<std::pair<double, double>>: [[a, b], ...] with a increasing
  kIntegers,  // std::vector<int>: [a, b, ...], none twice
};

// The values a parameter may take: each number (each coordinate of a point, each value of a list, a
// table's second column) lies within [min, max], either end exclusive where said.
struct ParamRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;

  bool contains(double v) const {
    return (min_exclusive ? v > min : v >= min) && (max_exclusive ? v < max : v <= max);
  }
  bool bounded() const {
    return min > -std::numeric_limits<double>::infinity() || max < std::numeric_limits<double>::infinity();
  }
};

namespace param_detail {

using Raw = void (*)();

template <class B>
struct MemberOps {
  ParamShape shape;
  std::size_t point_size;  // kPoint: 2 or 3
  bool optional;           // an std::optional member: absent is nothing
  ParamValue (*get)(Raw, const B&);
  void (*set)(Raw, B&, const ParamValue&);
  std::vector<std::string_view> (*spellings)();  // kChoice: the enumeration's
};

// How a member of type T is written: its shape, and its value to and from a ParamValue.
template <class T>
struct Traits;

template <>
struct Traits<double> {
  static constexpr ParamShape kShape = ParamShape::kNumber;
  static ParamValue get(const double& v) { return v; }
  static void set(double& m, const ParamValue& v) { m = v.number(); }
};
template <>
struct Traits<int> {
  static constexpr ParamShape kShape = ParamShape::kInteger;
  static ParamValue get(const int& v) { return v; }
  static void set(int& m, const ParamValue& v) { m = static_cast<int>(v.integer()); }
};
template <>
struct Traits<long> {
  static constexpr ParamShape kShape = ParamShape::kInteger;
  static ParamValue get(const long& v) { return v; }
  static void set(long& m, const ParamValue& v) { m = v.integer(); }
};
template <>
struct Traits<bool> {
  static constexpr ParamShape kShape = ParamShape::kFlag;
  static ParamValue get(const bool& v) { return v; }
  static void set(bool& m, const ParamValue& v) { m = v.flag(); }
};
template <>
struct Traits<std::string> {
  static constexpr ParamShape kShape = ParamShape::kText;
  static ParamValue get(const std::string& v) { return v; }
  static void set(std::string& m, const ParamValue& v) { m = v.text(); }
};
template <NamedEnum E>
struct Traits<E> {
  static constexpr ParamShape kShape = ParamShape::kChoice;
  static ParamValue get(const E& v) { return name_of(v); }
  static void set(E& m, const ParamValue& v) {
    const E* found = value_named<E>(v.text());
    if (!found) throw InternalError("no spelling '" + v.text() + "' to set");
    m = *found;
  }
};
template <class Scalar, int N>
struct Traits<Eigen::Matrix<Scalar, N, 1>> {
  using V = Eigen::Matrix<Scalar, N, 1>;
  static constexpr ParamShape kShape = ParamShape::kPoint;
  static ParamValue get(const V& v) {
    ParamValue::List out;
    for (int i = 0; i < N; ++i) out.emplace_back(static_cast<double>(v[i]));
    return out;
  }
  static void set(V& m, const ParamValue& v) {
    const ParamValue::List& l = v.list();
    if (l.size() != N) throw InternalError("a point of the wrong size to set");
    for (int i = 0; i < N; ++i) m[i] = static_cast<Scalar>(l[static_cast<std::size_t>(i)].number());
  }
};
template <>
struct Traits<std::vector<Eigen::Vector2d>> {
  static constexpr ParamShape kShape = ParamShape::kPolygon;
  static ParamValue get(const std::vector<Eigen::Vector2d>& v) {
    ParamValue::List out;
    for (const Eigen::Vector2d& p : v) out.push_back(Traits<Eigen::Vector2d>::get(p));
    return out;
  }
  static void set(std::vector<Eigen::Vector2d>& m, const ParamValue& v) {
    m.clear();
    for (const ParamValue& p : v.list()) Traits<Eigen::Vector2d>::set(m.emplace_back(), p);
  }
};
template <>
struct Traits<std::vector<std::vector<Eigen::Vector2d>>> {
  using Polygon = std::vector<Eigen::Vector2d>;
  static constexpr ParamShape kShape = ParamShape::kPolygons;
  static ParamValue get(const std::vector<Polygon>& v) {
    ParamValue::List out;
    for (const Polygon& p : v) out.push_back(Traits<Polygon>::get(p));
    return out;
  }
  static void set(std::vector<Polygon>& m, const ParamValue& v) {
    m.clear();
    for (const ParamValue& p : v.list()) Traits<Polygon>::set(m.emplace_back(), p);
  }
};
template <>
struct Traits<std::vector<std::pair<double, double>>> {
  static constexpr ParamShape kShape = ParamShape::kTable;
  static ParamValue get(const std::vector<std::pair<double, double>>& v) {
    ParamValue::List out;
    for (const auto& [a, b] : v) out.emplace_back(ParamValue::List{a, b});
    return out;
  }
  static void set(std::vector<std::pair<double, double>>& m, const ParamValue& v) {
    m.clear();
    for (const ParamValue& row : v.list())
      m.emplace_back(row.list().at(0).number(), row.list().at(1).number());
  }
};
template <>
struct Traits<std::vector<int>> {
  static constexpr ParamShape kShape = ParamShape::kIntegers;
  static ParamValue get(const std::vector<int>& v) {
    ParamValue::List out(v.begin(), v.end());
    return out;
  }
  static void set(std::vector<int>& m, const ParamValue& v) {
    m.clear();
    for (const ParamValue& x : v.list()) m.push_back(static_cast<int>(x.integer()));
  }
};
// An optional member: absent is nothing (monostate).
template <class T>
struct Traits<std::optional<T>> {
  static constexpr ParamShape kShape = Traits<T>::kShape;
  static ParamValue get(const std::optional<T>& v) { return v ? Traits<T>::get(*v) : ParamValue(); }
  static void set(std::optional<T>& m, const ParamValue& v) {
    if (v.empty()) {
      m.reset();
    } else {
      Traits<T>::set(m.emplace(), v);
    }
  }
};

template <class T>
constexpr std::size_t point_size() {
  if constexpr (requires { T::RowsAtCompileTime; })
    return static_cast<std::size_t>(T::RowsAtCompileTime);
  else
    return 0;
}

template <class T>
struct Unwrapped {
  using type = T;
  static constexpr bool kOptional = false;
};
template <class T>
struct Unwrapped<std::optional<T>> {
  using type = T;
  static constexpr bool kOptional = true;
};

template <class T>
std::vector<std::string_view> spellings() {
  using U = typename Unwrapped<T>::type;
  std::vector<std::string_view> out;
  if constexpr (NamedEnum<U>)
    for (const auto& n : enum_names(U{})) out.push_back(n.name);
  return out;
}

template <class B, class T>
inline const MemberOps<B> kOps = {
    Traits<T>::kShape,
    point_size<typename Unwrapped<T>::type>(),
    Unwrapped<T>::kOptional,
    [](Raw raw, const B& b) {
      const auto f = reinterpret_cast<T& (*)(B&)>(raw);
      return Traits<T>::get(f(const_cast<B&>(b)));
    },
    [](Raw raw, B& b, const ParamValue& v) {
      const auto f = reinterpret_cast<T& (*)(B&)>(raw);
      Traits<T>::set(f(b), v);
    },
    &spellings<T>,
};

}  // namespace param_detail

// The struct member a parameter sets: made by BT_MEMBER(Block, path.to.member); empty for a parameter its
// block's own code reads.
template <class B>
class ParamMember {
 public:
  ParamMember() = default;
  template <class T>
  explicit ParamMember(T& (*access)(B&))
      : raw_(reinterpret_cast<param_detail::Raw>(access)), ops_(&param_detail::kOps<B, T>) {}

  explicit operator bool() const { return ops_ != nullptr; }
  ParamShape shape() const { return ops_ ? ops_->shape : ParamShape::kNone; }
  std::size_t point_size() const { return ops_ ? ops_->point_size : 0; }
  bool optional() const { return ops_ && ops_->optional; }
  std::vector<std::string_view> spellings() const {
    return ops_ ? ops_->spellings() : std::vector<std::string_view>{};
  }
  ParamValue get(const B& b) const { return ops_->get(raw_, b); }
  void set(B& b, const ParamValue& v) const { ops_->set(raw_, b, v); }

 private:
  param_detail::Raw raw_ = nullptr;
  const param_detail::MemberOps<B>* ops_ = nullptr;
};

// What a declaration says apart from the member: everything the docs and the readers need.
struct ParamInfo {
  std::string_view key;  // dotted path inside its block ("boundary.passes")
  Dimension dim = Dimension::kDimensionless;
  // The default as a user writes it ("0.83 in", "[0, 0]", "none"); empty: required, or derived when absent
  // (`derived`, the meaning says how).
  std::string_view default_text;
  ParamRange range;
  std::string_view meaning;  // one line
  std::string_view source;   // patent paragraph, paper, machine data, "estimate", or the code that uses it
  bool derived = false;      // absent means "derived from other parameters" (the meaning says how)
  // A bool member written as one of two words (false's, then true's), or a text member limited to these.
  std::span<const std::string_view> choices = {};
  bool none_is_empty = false;  // text: "none" in a file is the empty text (a machine code it lacks)
  Dimension column_dim = Dimension::kDimensionless;  // kTable: the first column's (the second is `dim`)
  std::size_t min_points = 1;                        // kPolygon, kPolygons: at least this many points
  bool nonzero = false;                              // kPoint: not all zero (a direction)
  std::string_view
      form;  // without a member: how the value is written, for the docs ("[lower, upper] length")

  bool required() const { return default_text.empty() && !derived; }
};

// One declaration in a table for block `B`: what it says, and the member of `B` it sets.
template <class B>
struct Param : ParamInfo {
  ParamMember<B> member;

  Param(ParamInfo info, ParamMember<B> m = {}) : ParamInfo(info), member(m) {}

  ParamShape shape() const { return member.shape(); }
  // The words a choice is written with: the declared choices, else the enumeration's spellings.
  std::vector<std::string_view> spellings() const {
    if (!choices.empty()) return {choices.begin(), choices.end()};
    return member.spellings();
  }
  // The member's value as a file writes it: a bool with choices by its word, an empty text that
  // `none_is_empty` as "none".
  ParamValue get(const B& b) const {
    ParamValue v = member.get(b);
    if (!choices.empty() && shape() == ParamShape::kFlag) return std::string(choices[v.flag() ? 1 : 0]);
    if (none_is_empty && shape() == ParamShape::kText && v.text().empty()) return std::string("none");
    return v;
  }
  // Sets the member from a value as a file writes it (the inverse of get), which the reader has checked.
  void set(B& b, const ParamValue& v) const {
    if (!choices.empty() && shape() == ParamShape::kFlag) return member.set(b, v.text() == choices[1]);
    if (none_is_empty && shape() == ParamShape::kText && v.text() == "none")
      return member.set(b, std::string());
    member.set(b, v);
  }
};

// The member `path` of a `Block`, for a declaration: BT_MEMBER(SectionParams, boundary.passes).
#define BT_MEMBER(Block, path) \
  ::beadtwin::ParamMember<Block>(+[](Block & bt_block_) -> auto& { return bt_block_.path; })

// The declaration of `key` in `table`; throws InternalError when there is none (a code defect).
template <class B>
const Param<B>& find_param(std::span<const Param<B>> table, std::string_view key) {
  for (const Param<B>& p : table)
    if (p.key == key) return p;
  throw InternalError("no parameter '" + std::string(key) + "' declared");
}

// The first number of `value` outside the declared range, or nullopt: the number itself, each coordinate
// of a point or polygon, each value of a list, a table's second column.
std::optional<double> first_out_of_range(const ParamInfo& info, ParamShape shape, const ParamValue& value);

// "key: value 0 mm is out of range; ..." for every member of `b` whose value lies outside its declared
// range (derived values too: what they are derived as must be a value a user could give).
template <class B>
std::vector<std::string> range_problems(std::span<const Param<B>> table, const B& b) {
  std::vector<std::string> out;
  for (const Param<B>& p : table) {
    if (!p.member || !p.range.bounded()) continue;
    if (const std::optional<double> bad = first_out_of_range(p, p.shape(), p.member.get(b)))
      out.push_back(std::string(p.key) + ": " + out_of_range_text(p, *bad));
  }
  return out;
}

// How a parameter's type reads in the docs: "length", "whole number", "true/false", "one of a, b, c", ...
std::string param_type_text(const ParamInfo& info, ParamShape shape, std::size_t point_size,
                            std::span<const std::string_view> spellings);
// Its range as the docs print it (">= 0, <= 50 mm"), or empty when it has none to print.
std::string param_range_text(const ParamInfo& info, ParamShape shape);
// "value 0 mm is out of range; expected a value in (0, 100] mm": the message for a value out of range.
std::string out_of_range_text(const ParamInfo& info, double value);

}  // namespace beadtwin
