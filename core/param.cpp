#include "core/param.hpp"

#include <cmath>

#include <fmt/format.h>

namespace beadtwin {
namespace {

[[noreturn]] void wrong_kind(std::string_view asked) {
  throw InternalError(fmt::format("a parameter value asked for as {} holds something else", asked));
}

std::string number_text(double v) {
  return fmt::format("{:g}", v);
}

}  // namespace

double ParamValue::number() const {
  if (const double* d = std::get_if<double>(&value)) return *d;
  if (const long* l = std::get_if<long>(&value)) return static_cast<double>(*l);
  wrong_kind("a number");
}

long ParamValue::integer() const {
  if (const long* l = std::get_if<long>(&value)) return *l;
  wrong_kind("a whole number");
}

bool ParamValue::flag() const {
  if (const bool* b = std::get_if<bool>(&value)) return *b;
  wrong_kind("true or false");
}

const std::string& ParamValue::text() const {
  if (const std::string* s = std::get_if<std::string>(&value)) return *s;
  wrong_kind("text");
}

const ParamValue::List& ParamValue::list() const {
  if (const List* l = std::get_if<List>(&value)) return *l;
  wrong_kind("a list");
}

std::string spellings_text(std::span<const std::string_view> names, std::string_view last_joint) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += std::string(i == 0 ? "" : i + 1 == names.size() ? last_joint : ", ") + std::string(names[i]);
  return out;
}

std::string param_type_text(const ParamInfo& info, ParamShape shape, std::size_t point_size,
                            std::span<const std::string_view> spellings) {
  const std::string dim(dimension_name(info.dim));
  switch (shape) {
    case ParamShape::kNumber:
      return dim;
    case ParamShape::kInteger:
      return "integer";
    case ParamShape::kFlag:
      return spellings.empty() ? "true/false" : spellings_text(spellings);
    case ParamShape::kText:
      return spellings.empty() ? "text" : spellings_text(spellings);
    case ParamShape::kChoice:
      return spellings_text(spellings);
    case ParamShape::kPoint:
      return fmt::format("[x, y{}] {}", point_size == 3 ? ", z" : "", dim);
    case ParamShape::kPolygon:
      return fmt::format("[[x, y], ...] {}", dim);
    case ParamShape::kPolygons:
      return fmt::format("[[x, y], ...] {} (or a list of them)", dim);
    case ParamShape::kTable:
      return fmt::format("[[{}, {}], ...]", dimension_name(info.column_dim), dim);
    case ParamShape::kIntegers:
      return "list of integers";
    case ParamShape::kNone:
      return std::string(info.form);
  }
  return "?";
}

std::string param_range_text(const ParamInfo& info, ParamShape shape) {
  if (shape == ParamShape::kFlag || shape == ParamShape::kText || shape == ParamShape::kChoice) return "";
  const ParamRange& r = info.range;
  const std::string lo = std::isinf(r.min) ? "" : (r.min_exclusive ? "> " : ">= ") + number_text(r.min);
  const std::string hi = std::isinf(r.max) ? "" : (r.max_exclusive ? "< " : "<= ") + number_text(r.max);
  std::string text = lo.empty() ? hi : hi.empty() ? lo : lo + ", " + hi;
  const std::string_view unit = internal_unit(info.dim);
  if (!text.empty() && !unit.empty()) text += " " + std::string(unit);
  return text;
}

std::optional<double> first_out_of_range(const ParamInfo& info, ParamShape shape, const ParamValue& value) {
  if (value.empty()) return std::nullopt;
  switch (shape) {
    case ParamShape::kNumber:
    case ParamShape::kInteger:
      return info.range.contains(value.number()) ? std::nullopt : std::optional<double>(value.number());
    case ParamShape::kTable:
      for (const ParamValue& row : value.list())
        if (const auto bad = first_out_of_range(info, ParamShape::kNumber, row.list().at(1))) return bad;
      return std::nullopt;
    case ParamShape::kPoint:
    case ParamShape::kIntegers:
      for (const ParamValue& x : value.list())
        if (const auto bad = first_out_of_range(info, ParamShape::kNumber, x)) return bad;
      return std::nullopt;
    case ParamShape::kPolygon:
      for (const ParamValue& point : value.list())
        if (const auto bad = first_out_of_range(info, ParamShape::kPoint, point)) return bad;
      return std::nullopt;
    case ParamShape::kPolygons:
      for (const ParamValue& polygon : value.list())
        if (const auto bad = first_out_of_range(info, ParamShape::kPolygon, polygon)) return bad;
      return std::nullopt;
    case ParamShape::kNone:
    case ParamShape::kFlag:
    case ParamShape::kText:
    case ParamShape::kChoice:
      return std::nullopt;
  }
  return std::nullopt;
}

std::string out_of_range_text(const ParamInfo& info, double value) {
  const std::string unit(internal_unit(info.dim));
  const std::string with_unit = unit.empty() ? "" : " " + unit;
  const ParamRange& r = info.range;
  std::string range;
  if (std::isinf(r.max))
    range = fmt::format("{} {}{}", r.min_exclusive ? "above" : "at least", r.min, with_unit);
  else if (std::isinf(r.min))
    range = fmt::format("{} {}{}", r.max_exclusive ? "below" : "at most", r.max, with_unit);
  else
    range = fmt::format("in {}{}, {}{}{}", r.min_exclusive ? "(" : "[", r.min, r.max,
                        r.max_exclusive ? ")" : "]", with_unit);
  return fmt::format("value {}{} is out of range; expected a value {}", value, with_unit, range);
}

}  // namespace beadtwin
