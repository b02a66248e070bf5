// Deterministic area-weighted sampling of a triangle, for measuring a quantity over a triangulated surface
// (the stock over the CAD, the deviation of the printed skin: sim/cad_compare.hpp).
//
// A triangle is sampled on a grid in its own plane: rows of equal height no taller than the spacing,
// parallel to its longest edge, each row cut into columns of equal width no wider than the spacing. Each
// cell of the grid holds a part of the triangle (a convex polygon of at most eight corners); its sample is
// that part's centroid, weighted by its area. So a sample stands for at most spacing² of surface whatever
// the triangle's shape: a sliver narrower than the spacing (a long thin CAD triangle) takes one row, about
// length / spacing samples, not the (length / spacing)² of a subdivision into equal triangles. The rows are
// walked back and forth, so that each sample lies beside the one before it (a search from the last sample's
// answer stays small). A triangle that fits one cell is one sample at its centroid.
//
// Preconditions throughout: the corners are finite, mm; the spacing is positive and finite, mm. A triangle
// without area is sampled all the same (its cells have no area; their samples are their corners' mean).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

#include <Eigen/Core>

namespace beadtwin::sim {

// A triangle's sampling grid: the triangle laid flat with its longest edge along x from the origin and its
// third corner at (apex_x, height).
struct TriangleGrid {
  Eigen::Vector3d origin, x_axis, y_axis;  // the longest edge's first corner; along it; towards the third
  double length = 0.0, apex_x = 0.0, height = 0.0;  // mm
  double spacing = 0.0;                             // mm
  double rows = 0.0;                                // ≥ 1, of height / rows each

  // `a`, `b`, `c`: the corners, mm; `spacing_mm`: the widest a row or column may be.
  TriangleGrid(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
               double spacing_mm);

  // The triangle's x-extent at height y: [left(y), right(y)].
  double left(double y) const { return height > 0 ? apex_x * (y / height) : 0.0; }
  double right(double y) const { return height > 0 ? length + (apex_x - length) * (y / height) : length; }
  double row_bottom(double j) const { return j == 0 ? 0.0 : height * (j / rows); }
  double row_top(double j) const { return j + 1 == rows ? height : height * ((j + 1) / rows); }
  // Row j's extent in x and its columns (≥ 1).
  std::pair<double, double> row_extent(double j) const {
    const double y0 = row_bottom(j), y1 = row_top(j);
    return {std::min(left(y0), left(y1)), std::max(right(y0), right(y1))};
  }
  double columns(double j) const {
    const auto [lo, hi] = row_extent(j);
    return std::max(1.0, std::ceil((hi - lo) / spacing));
  }
  Eigen::Vector3d to_3d(double x, double y) const { return origin + x * x_axis + y * y_axis; }
};

// One cell of a triangle's sampling grid: the part of the triangle in it, a convex polygon.
struct SampleCell {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // its centroid: the sample, mm
  double area = 0.0;                                // mm²
  double radius = 0.0;                              // the distance from the sample to its farthest corner, mm
  std::array<Eigen::Vector3d, 8> corner;
  std::size_t corners = 0;

  SampleCell() { corner.fill(Eigen::Vector3d::Zero()); }
};

namespace detail {

using Flat2 = std::array<double, 2>;

// The part of row polygon `row` (four corners, relative to the row's lower left) between x0 and x1
// (Sutherland and Hodgman), into `part`; returns its corners.
inline std::size_t clip_row(const std::array<Flat2, 4>& row, double x0, double x1,
                            std::array<Flat2, 8>& part) {
  std::array<Flat2, 8> cut{};
  std::size_t cuts = 0, corners = 0;
  for (std::size_t k = 0; k < row.size(); ++k) {
    const Flat2& u = row[k];
    const Flat2& v = row[(k + 1) % row.size()];
    const bool u_in = u[0] >= x0, v_in = v[0] >= x0;
    if (u_in) cut[cuts++] = u;
    if (u_in != v_in) cut[cuts++] = {x0, u[1] + (v[1] - u[1]) * ((x0 - u[0]) / (v[0] - u[0]))};
  }
  for (std::size_t k = 0; k < cuts; ++k) {
    const Flat2& u = cut[k];
    const Flat2& v = cut[(k + 1) % cuts];
    const bool u_in = u[0] <= x1, v_in = v[0] <= x1;
    if (u_in) part[corners++] = u;
    if (u_in != v_in) part[corners++] = {x1, u[1] + (v[1] - u[1]) * ((x1 - u[0]) / (v[0] - u[0]))};
  }
  return corners;
}

// The centroid of polygon `part` (its corners' mean when it has no area) and twice its area.
inline std::pair<Flat2, double> centroid(const std::array<Flat2, 8>& part, std::size_t corners) {
  double twice_area = 0.0, cx = 0.0, cy = 0.0, mx = 0.0, my = 0.0;
  for (std::size_t k = 0; k < corners; ++k) {
    const Flat2& u = part[k];
    const Flat2& v = part[(k + 1) % corners];
    const double w = u[0] * v[1] - v[0] * u[1];
    twice_area += w;
    cx += (u[0] + v[0]) * w;
    cy += (u[1] + v[1]) * w;
    mx += u[0];
    my += u[1];
  }
  Flat2 c{0.0, 0.0};
  if (twice_area > 0) {
    c = {cx / (3.0 * twice_area), cy / (3.0 * twice_area)};
  } else if (corners > 0) {
    c = {mx / static_cast<double>(corners), my / static_cast<double>(corners)};
  }
  return {c, twice_area};
}

inline void set_radius(SampleCell& cell) {
  cell.radius = 0.0;
  for (std::size_t k = 0; k < cell.corners; ++k)
    cell.radius = std::max(cell.radius, (cell.corner[k] - cell.point).norm());
}

}  // namespace detail

// Calls `f(const SampleCell&)` for every cell of triangle (a, b, c) at `spacing_mm`, in a fixed order.
template <class F>
void for_each_cell(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   double spacing_mm, F&& f) {
  const TriangleGrid grid(a, b, c, spacing_mm);
  SampleCell cell;
  if (grid.rows == 1 && grid.columns(0) == 1) {  // one cell holds it whole (most of the print's triangles)
    cell.point = (a + b + c) / 3.0;
    cell.area = 0.5 * grid.length * grid.height;
    cell.corner[0] = a, cell.corner[1] = b, cell.corner[2] = c;
    cell.corners = 3;
    detail::set_radius(cell);
    f(static_cast<const SampleCell&>(cell));
    return;
  }
  for (double j = 0; j < grid.rows; ++j) {
    const double y0 = grid.row_bottom(j), y1 = grid.row_top(j);
    // The row's part of the triangle, a trapezoid (a triangle in the top row), relative to (lo, y0).
    const auto [lo, hi] = grid.row_extent(j);
    const std::array<detail::Flat2, 4> row{{{grid.left(y0) - lo, 0.0},
                                            {grid.right(y0) - lo, 0.0},
                                            {grid.right(y1) - lo, y1 - y0},
                                            {grid.left(y1) - lo, y1 - y0}}};
    const double n = grid.columns(j), width = hi - lo;
    const bool backwards = static_cast<long long>(j) % 2 == 1;
    for (double i = 0; i < n; ++i) {
      const double column = backwards ? n - 1 - i : i;
      const double x0 = column == 0 ? 0.0 : width * (column / n);
      const double x1 = column + 1 == n ? width : width * ((column + 1) / n);
      std::array<detail::Flat2, 8> part{};
      const std::size_t corners = detail::clip_row(row, x0, x1, part);
      const auto [centre, twice_area] = detail::centroid(part, corners);
      cell.point = grid.to_3d(lo + centre[0], y0 + centre[1]);
      cell.area = std::max(0.0, 0.5 * twice_area);
      cell.corners = corners;
      for (std::size_t k = 0; k < corners; ++k) cell.corner[k] = grid.to_3d(lo + part[k][0], y0 + part[k][1]);
      detail::set_radius(cell);
      f(static_cast<const SampleCell&>(cell));
    }
  }
}

// Calls `sample(const Eigen::Vector3d& point_mm, double area_mm2)` for every sample of (a, b, c), in
// for_each_cell's order.
template <class Sample>
void sample_points(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   double spacing_mm, Sample&& sample) {
  for_each_cell(a, b, c, spacing_mm, [&](const SampleCell& cell) { sample(cell.point, cell.area); });
}

// How many samples for_each_cell takes of (a, b, c) at `spacing_mm`, counting no further than `limit`
// (then limit + 1).
std::size_t count_samples(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                          double spacing_mm, std::size_t limit);

}  // namespace beadtwin::sim
