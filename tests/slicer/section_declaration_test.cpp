// The section's declaration (slicer/section_params.hpp) against the planner: every value the declaration
// lets a scenario give is one the planner plans, and every value beyond it the planner refuses, so the
// loader's ranges are the planner's.
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "slicer/plan.hpp"
#include "slicer/section_params.hpp"

namespace beadtwin::slicer {
namespace {

// A small filled section two layers high: a box slice, or (for the variable layer height, which only an
// AM Outline takes) a short outline path.
SectionParams base_section(const Param<SectionParams>& p) {
  SectionParams s;
  s.name = "s";
  s.z_min_mm = 0.0;
  s.layer_height_mm = 5.0;
  s.bead_width_mm = 20.0;
  s.print_speed_mm_s = 50.0;
  s.travel_speed_mm_s = 200.0;
  s.fill.enabled = true;
  if (p.key.starts_with("variable_height.")) s.outline_path = {{0, 0}, {4, 0}};
  return s;
}

// What the loader requires of the keys beside the one set (scenarios/input/section_block.cpp): a bead at
// least as wide as it is thick, a maximum overlap at least the overlap, the section two layers high.
void keep_consistent(SectionParams& s, std::string_view key) {
  if (key == "bead_width")
    s.layer_height_mm = std::min(s.layer_height_mm, s.bead_width_mm);
  else
    s.bead_width_mm = std::max(s.bead_width_mm, s.layer_height_mm);
  if (key == "boundary.max_overlap")
    s.boundary.overlap = std::min(s.boundary.overlap, s.boundary.max_overlap);
  if (key == "boundary.overlap")
    s.boundary.max_overlap = std::max(s.boundary.overlap, s.boundary.max_overlap);
  if (key == "fill.max_overlap") s.fill.overlap = std::min(s.fill.overlap, s.fill.max_overlap);
  if (key == "fill.overlap") s.fill.max_overlap = std::max(s.fill.overlap, s.fill.max_overlap);
  s.fill.boundary_overlap = s.fill.boundary_side_overlap = s.fill.overlap;
  s.z_max_mm = s.z_min_mm + 2 * s.layer_height_mm;
}

// The value just inside (inside = true) or just beyond the end of the range at `high` or low; nullopt
// where that end is open.
std::optional<double> near_end(const Param<SectionParams>& p, bool high, bool inside) {
  const ParamRange& r = p.range;
  const double end = high ? r.max : r.min;
  if (std::isinf(end)) return std::nullopt;
  const bool whole = p.shape() == ParamShape::kInteger;
  const double step = whole ? 1.0 : std::max(1e-3, 1e-3 * std::abs(end));
  const bool exclusive = high ? r.max_exclusive : r.min_exclusive;
  const double sign = high ? -1.0 : 1.0;  // towards the inside
  if (inside) return exclusive ? end + sign * step : end;
  return exclusive ? end : end - sign * step;
}

ParamValue as_value(const Param<SectionParams>& p, double v) {
  return p.shape() == ParamShape::kInteger ? ParamValue(static_cast<long>(v)) : ParamValue(v);
}

TEST(SectionDeclaration, ThePlannerPlansEveryDeclaredRangeEndAndRefusesBeyond) {
  const TriangleMesh part = make_box({120, 80, 12});
  const MotionLimits motion;
  int checked = 0;
  for (const Param<SectionParams>& p : section_params()) {
    if (!p.member || p.derived || !p.range.bounded()) continue;
    if (p.shape() != ParamShape::kNumber && p.shape() != ParamShape::kInteger) continue;
    for (const bool high : {false, true}) {
      for (const bool inside : {true, false}) {
        const std::optional<double> v = near_end(p, high, inside);
        if (!v) continue;
        SectionParams s = base_section(p);
        p.set(s, as_value(p, *v));
        if (inside) keep_consistent(s, p.key);
        s.z_max_mm = s.z_min_mm + 2 * s.layer_height_mm;
        const std::string what = fmt::format("{} = {}", p.key, *v);
        if (inside) {
          EXPECT_NO_THROW((void)plan_toolpath(part, {s}, motion)) << what;
          ++checked;
        } else {
          try {
            (void)plan_toolpath(part, {s}, motion);
            ADD_FAILURE() << what << " is beyond the declared range but was planned";
          } catch (const InputError& e) {
            EXPECT_EQ(e.key(), "sections.s." + std::string(p.key)) << what << ": " << e.what();
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 60);  // the declaration bounds most of a section's numbers
}

// Points and polygons: each coordinate within the declared range.
TEST(SectionDeclaration, ThePlannerRefusesAnOutlinePointBeyondTheDeclaredRange) {
  SectionParams s = base_section(find_param(section_params(), "outline.points"));
  s.outline_path = {{0, 0}, {2 * kMaxPartSizeMm, 0}};
  s.z_max_mm = 10.0;
  try {
    (void)plan_toolpath(TriangleMesh{}, {s}, MotionLimits{});
    ADD_FAILURE() << "an outline 200 m long was planned";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "sections.s.outline.points");
  }
}

// Every enumeration a section takes has a spelling for each of its values, and each spelling reads back.
TEST(SectionDeclaration, EveryChoiceHasOneSpellingPerValue) {
  for (const FillStyleKind style : {FillStyleKind::kOneWay, FillStyleKind::kSimpleZigzag,
                                    FillStyleKind::kSmartZigzag, FillStyleKind::kSmartZigzagConstantOverlap,
                                    FillStyleKind::kSparseZigzag, FillStyleKind::kVariableBeadRegions}) {
    const std::string_view name = to_string(style);
    EXPECT_NE(name, "?");
    ASSERT_NE(value_named<FillStyleKind>(name), nullptr) << name;
    EXPECT_EQ(*value_named<FillStyleKind>(name), style);
  }
  for (const SlicePlane plane : {SlicePlane::kTop, SlicePlane::kFront, SlicePlane::kSide})
    EXPECT_EQ(*value_named<SlicePlane>(to_string(plane)), plane);
}

}  // namespace
}  // namespace beadtwin::slicer
