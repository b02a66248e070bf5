// Boustrophedon cell decomposition of a region along y: the region cut into cells that every horizontal
// line crosses in one piece, so a serpentine of horizontal lines can fill each cell without crossing a hole
// (the smart zigzag fill styles, patent (59)-(61)). Pure geometry; coordinates in mm.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

// A stretch of a horizontal line, x0 <= x1, mm.
struct Span {
  double x0 = 0;
  double x1 = 0;
};

// The cells of one region, with the neighbours across each cell's ends.
class BoustrophedonCells {
 public:
  // `region`: closed contours, outer counter-clockwise, holes clockwise, not self-intersecting (as Clipper
  // gives them). The cells are split at every vertex height where the region's cross-section changes its
  // number of pieces (a hole begins or ends, the outline forks or joins), and where a side jumps sideways
  // by more than `split_jump_mm` (a step, like an L's), so a cell's band ends where its width does.
  BoustrophedonCells(const Polygons& region, double split_jump_mm);

  struct Cell {
    double y_lo = 0;  // band of heights the cell covers, mm
    double y_hi = 0;
    // Whether a line at the band's end belongs to this cell. Where one cell meets several across a height,
    // the line along that height is the single cell's (it is one piece there); the others stop short. At a
    // step between two cells it is the wider one's.
    bool lo_closed = true;
    bool hi_closed = true;
    std::vector<std::size_t> below;   // neighbouring cells across y_lo
    std::vector<std::size_t> above;   // across y_hi
    std::vector<std::size_t> pieces;  // internal: trapezoids bottom to top
  };

  const std::vector<Cell>& cells() const { return cells_; }
  // The cell's extent at height `y` (clamped to its band); at a height where the cell's side jumps (a
  // horizontal edge) the wider of the two.
  Span span(std::size_t cell, double y) const;
  // Whether the cell's lines include one at height `y`: inside its band, or on a closed end of it.
  bool owns(std::size_t cell, double y) const;
  // The closed region's cross-section at height `y`: sorted, disjoint spans.
  std::vector<Span> cross_section(double y) const;
  double y_min() const { return y_min_; }
  double y_max() const { return y_max_; }

 private:
  struct Edge {
    Eigen::Vector2d a, b;  // a.y() < b.y()
    double x_at(double y) const;
  };
  struct Piece {  // the part of the region between two edges in one slab between vertex heights
    double y0 = 0, y1 = 0;
    Edge left, right;
    std::vector<std::size_t> down, up;  // connected pieces in the slabs below and above
    Span at(double y) const { return {left.x_at(y), right.x_at(y)}; }
  };

  std::vector<Piece> pieces_;
  std::vector<Cell> cells_;
  double y_min_ = 0, y_max_ = 0;
};

}  // namespace beadtwin::slicer
