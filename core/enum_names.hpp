// The one spelling of each value of an enumeration: the word scenario files, messages, reports and docs
// use for it. An enumeration that users write declares its spellings once, beside it:
//
//   enum class SlicePlane : std::uint8_t { kTop, kFront, kSide };
//   inline constexpr EnumName<SlicePlane> kSlicePlaneNames[] = {
//       {SlicePlane::kTop, "top"}, {SlicePlane::kFront, "front"}, {SlicePlane::kSide, "side"}};
//   constexpr std::span<const EnumName<SlicePlane>> enum_names(SlicePlane) { return kSlicePlaneNames; }
//
// and everything that reads or writes the enumeration goes through enum_names (found by argument-dependent
// lookup): to_string, the scenario reader, `beadtwin params`.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace beadtwin {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

// An enumeration with declared spellings.
template <class E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
  { enum_names(e) } -> std::convertible_to<std::span<const EnumName<E>>>;
};

// The spelling of `value`; "?" for a value the enumeration's names leave out (a defect: the name test in
// tests/core checks every declared enumeration).
template <NamedEnum E>
constexpr std::string_view name_of(E value) {
  for (const EnumName<E>& n : enum_names(value))
    if (n.value == value) return n.name;
  return "?";
}

// The value spelt `name`, or nullptr when none is.
template <NamedEnum E>
constexpr const E* value_named(std::string_view name) {
  for (const EnumName<E>& n : enum_names(E{}))
    if (n.name == name) return &n.value;
  return nullptr;
}

// The spellings as a list for a message or a doc: "a, b or c".
std::string spellings_text(std::span<const std::string_view> names, std::string_view last_joint = " or ");

template <NamedEnum E>
std::string spellings_text(std::string_view last_joint = " or ") {
  std::string out;
  const auto names = enum_names(E{});
  for (std::size_t i = 0; i < names.size(); ++i)
    out += std::string(i == 0 ? "" : i + 1 == names.size() ? last_joint : ", ") + std::string(names[i].name);
  return out;
}

}  // namespace beadtwin
