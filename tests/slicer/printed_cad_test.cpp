// The CAD the sections print, in the machine frame: what the printed part is measured against.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::slicer {
namespace {

SectionParams sliced(const std::string& name, double z0, double z1, const std::string& body = "") {
  SectionParams s;
  s.name = name;
  s.body = body;
  s.z_min_mm = z0;
  s.z_max_mm = z1;
  s.layer_height_mm = 5;
  s.bead_width_mm = 20;
  return s;
}

// Two bodies: "a" at x in [0, 400], "b" at x in [400, 800].
TriangleMesh two_bodies() {
  TriangleMesh a = make_box({400, 300, 50});
  const TriangleMesh b = make_box({400, 300, 80}, {400, 0, 0});
  const int base = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  const std::size_t a_tris = a.triangles.size();
  for (auto t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  a.body.assign(a.triangles.size(), 1);
  std::fill(a.body.begin(), a.body.begin() + static_cast<std::ptrdiff_t>(a_tris), 0);
  a.body_names = {"a", "b"};
  return a;
}

TEST(PrintedCad, WholePartOnItsSlicePlane) {
  const TriangleMesh box = make_box({100, 60, 40}, {10, 20, 0});
  const auto top = printed_cad(box, {sliced("lower", 0, 20), sliced("upper", 20, 40)});
  ASSERT_TRUE(top);
  EXPECT_EQ(top->triangles.size(), box.triangles.size());  // once, not once per section
  EXPECT_TRUE(top->min_corner().isApprox(box.min_corner()));
  EXPECT_TRUE(top->max_corner().isApprox(box.max_corner()));
  // Laid on its front: the part's +Y becomes up, as the planner slices it.
  SectionParams front = sliced("front", 0, 60);
  front.slice_plane = SlicePlane::kFront;
  const auto laid = printed_cad(box, {front});
  ASSERT_TRUE(laid);
  const TriangleMesh expected = lay_down(box, SlicePlane::kFront);
  EXPECT_TRUE(laid->min_corner().isApprox(expected.min_corner()));
  EXPECT_TRUE(laid->max_corner().isApprox(expected.max_corner()));
  EXPECT_NEAR(laid->max_corner().z() - laid->min_corner().z(), 60.0, 1e-9);
}

TEST(PrintedCad, RaftsLiftThePartShiftsDoNot) {
  const TriangleMesh box = make_box({100, 60, 40});
  SectionParams s = sliced("s", 0, 40);
  s.rafts = 2;                // the part stands on two 5 mm layers
  s.shift_mm = {7, 0};        // moves the toolpath, not the part
  s.contact_offset_mm = 1.5;  // likewise
  const auto cad = printed_cad(box, {s});
  ASSERT_TRUE(cad);
  EXPECT_TRUE(cad->min_corner().isApprox(Eigen::Vector3d(0, 0, 10)));
  EXPECT_TRUE(cad->max_corner().isApprox(Eigen::Vector3d(100, 60, 50)));
}

TEST(PrintedCad, NamedBodiesOnly) {
  const TriangleMesh part = two_bodies();
  const auto a = printed_cad(part, {sliced("a1", 0, 25, "a"), sliced("a2", 25, 50, "a")});
  ASSERT_TRUE(a);
  EXPECT_EQ(a->triangles.size(), 12u);  // body a once
  EXPECT_NEAR(a->max_corner().x(), 400.0, 1e-9);
  const auto both = printed_cad(part, {sliced("a", 0, 50, "a"), sliced("b", 0, 80, "b")});
  ASSERT_TRUE(both);
  EXPECT_EQ(both->triangles.size(), 24u);
  EXPECT_NEAR(both->max_corner().x(), 800.0, 1e-9);
  EXPECT_THROW((void)printed_cad(part, {sliced("c", 0, 50, "c")}), InputError);
}

TEST(PrintedCad, AmOutlineSectionsHaveNone) {
  SectionParams outline = sliced("ring", 0, 10);
  outline.outline_path = {{0, 0}, {100, 0}, {100, 50}};
  EXPECT_FALSE(printed_cad(TriangleMesh{}, {outline}));
  // Beside a sliced section, an outline adds nothing to the CAD.
  const TriangleMesh box = make_box({100, 60, 40});
  const auto cad = printed_cad(box, {outline, sliced("box", 0, 40)});
  ASSERT_TRUE(cad);
  EXPECT_EQ(cad->triangles.size(), box.triangles.size());
}

}  // namespace
}  // namespace beadtwin::slicer
