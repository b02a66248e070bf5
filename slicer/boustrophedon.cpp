#include "slicer/boustrophedon.hpp"

#include <algorithm>
#include <limits>

namespace beadtwin::slicer {
namespace {

constexpr double kEps = 1e-9;      // heights closer than this are the same, mm
constexpr double kMinJoin = 1e-6;  // pieces join across a height only along more than this, mm

void add_unique(std::vector<std::size_t>& v, std::size_t i) {
  if (std::find(v.begin(), v.end(), i) == v.end()) v.push_back(i);
}

}  // namespace

double BoustrophedonCells::Edge::x_at(double y) const {
  const double t = std::clamp((y - a.y()) / (b.y() - a.y()), 0.0, 1.0);
  return a.x() + t * (b.x() - a.x());
}

BoustrophedonCells::BoustrophedonCells(const Polygons& region, double split_jump_mm) {
  std::vector<Edge> edges;
  std::vector<double> ys;
  for (const Polygon& poly : region) {
    for (std::size_t i = 0, n = poly.size(); i < n; ++i) {
      const Eigen::Vector2d& p = poly[i];
      const Eigen::Vector2d& q = poly[(i + 1) % n];
      ys.push_back(p.y());
      if (std::abs(p.y() - q.y()) > 1e-12) edges.push_back(p.y() < q.y() ? Edge{p, q} : Edge{q, p});
    }
  }
  if (edges.empty()) return;
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end(), [](double a, double b) { return b - a < kEps; }), ys.end());
  y_min_ = ys.front();
  y_max_ = ys.back();

  // Slabs between consecutive vertex heights: no vertex inside, so each piece is bounded by one edge on
  // either side; pieces of neighbouring slabs join where their spans overlap on the shared height.
  std::vector<std::size_t> previous;
  for (std::size_t k = 0; k + 1 < ys.size(); ++k) {
    const double y0 = ys[k], y1 = ys[k + 1], ym = 0.5 * (y0 + y1);
    std::vector<const Edge*> crossing;
    for (const Edge& e : edges)
      if (e.a.y() <= y0 + kEps && e.b.y() >= y1 - kEps) crossing.push_back(&e);
    std::sort(crossing.begin(), crossing.end(),
              [ym](const Edge* a, const Edge* b) { return a->x_at(ym) < b->x_at(ym); });
    std::vector<std::size_t> current;
    for (std::size_t i = 0; i + 1 < crossing.size(); i += 2) {
      Piece piece{y0, y1, *crossing[i], *crossing[i + 1], {}, {}};
      const std::size_t id = pieces_.size();
      for (std::size_t below : previous) {
        const Span a = pieces_[below].at(y0), b = piece.at(y0);
        if (std::min(a.x1, b.x1) - std::max(a.x0, b.x0) > kMinJoin) {
          pieces_[below].up.push_back(id);
          piece.down.push_back(below);
        }
      }
      pieces_.push_back(std::move(piece));
      current.push_back(id);
    }
    previous = std::move(current);
  }

  // A piece continues the cell below when the two are each other's only neighbour and meet without a step.
  const auto step = [this, split_jump_mm](std::size_t below, std::size_t above) {
    const Piece& a = pieces_[below];
    const Span s = a.at(a.y1), t = pieces_[above].at(a.y1);
    return std::abs(s.x0 - t.x0) > split_jump_mm || std::abs(s.x1 - t.x1) > split_jump_mm;
  };
  std::vector<std::size_t> cell_of(pieces_.size());
  for (std::size_t id = 0; id < pieces_.size(); ++id) {
    const Piece& p = pieces_[id];
    if (p.down.size() == 1 && pieces_[p.down[0]].up.size() == 1 && !step(p.down[0], id)) {
      cell_of[id] = cell_of[p.down[0]];
      cells_[cell_of[id]].y_hi = p.y1;
    } else {
      cell_of[id] = cells_.size();
      cells_.push_back(Cell{p.y0, p.y1, true, true, {}, {}, {}});
    }
    cells_[cell_of[id]].pieces.push_back(id);
  }
  for (std::size_t id = 0; id < pieces_.size(); ++id)
    for (std::size_t up : pieces_[id].up) {
      if (cell_of[id] == cell_of[up]) continue;
      add_unique(cells_[cell_of[id]].above, cell_of[up]);
      add_unique(cells_[cell_of[up]].below, cell_of[id]);
    }
  // The line along a shared height goes to the side that is one piece there (a fork's stem, a join's
  // top), at a step to the wider side; where both sides are several pieces, neither takes it.
  const auto width = [this](std::size_t c, double y) {
    const Span s = span(c, y);
    return s.x1 - s.x0;
  };
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    Cell& c = cells_[i];
    const auto single = [this](std::size_t other, bool other_above) {
      return (other_above ? cells_[other].below : cells_[other].above).size() == 1;
    };
    c.hi_closed = c.above.empty() || std::all_of(c.above.begin(), c.above.end(),
                                                 [&single](std::size_t a) { return single(a, true); });
    c.lo_closed = c.below.empty() || std::all_of(c.below.begin(), c.below.end(),
                                                 [&single](std::size_t b) { return single(b, false); });
    if (c.above.size() == 1 && c.hi_closed) c.hi_closed = width(i, c.y_hi) >= width(c.above[0], c.y_hi);
    if (c.below.size() == 1 && c.lo_closed) c.lo_closed = width(i, c.y_lo) > width(c.below[0], c.y_lo);
  }
}

Span BoustrophedonCells::span(std::size_t cell, double y) const {
  const Cell& c = cells_.at(cell);
  y = std::clamp(y, c.y_lo, c.y_hi);
  Span s{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (std::size_t id : c.pieces) {
    const Piece& p = pieces_[id];
    if (y < p.y0 - kEps || y > p.y1 + kEps) continue;
    const Span a = p.at(y);
    s.x0 = std::min(s.x0, a.x0);
    s.x1 = std::max(s.x1, a.x1);
  }
  return s;
}

bool BoustrophedonCells::owns(std::size_t cell, double y) const {
  const Cell& c = cells_.at(cell);
  if (std::abs(y - c.y_lo) <= kEps) return c.lo_closed;
  if (std::abs(y - c.y_hi) <= kEps) return c.hi_closed;
  return y > c.y_lo && y < c.y_hi;
}

std::vector<Span> BoustrophedonCells::cross_section(double y) const {
  std::vector<Span> spans;
  for (const Piece& p : pieces_)
    if (y >= p.y0 - kEps && y <= p.y1 + kEps) spans.push_back(p.at(y));
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.x0 < b.x0; });
  std::vector<Span> merged;
  for (const Span& s : spans) {
    if (!merged.empty() && s.x0 <= merged.back().x1 + kEps)
      merged.back().x1 = std::max(merged.back().x1, s.x1);
    else
      merged.push_back(s);
  }
  return merged;
}

}  // namespace beadtwin::slicer
