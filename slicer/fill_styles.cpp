#include "slicer/fill_styles.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "core/error.hpp"
#include "slicer/boustrophedon.hpp"

namespace beadtwin::slicer {
namespace {

// A turn may leave the grown region by this much (rounding of the offset), mm.
constexpr double kTurnSlack = 0.01;
// Lines shorter than this are points, not lines, mm.
constexpr double kMinLine = 1e-6;
// Fillet arcs: segments per quarter turn.
constexpr int kArcSegmentsPerQuarter = 8;

Eigen::Vector2d rotate(const Eigen::Vector2d& p, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

void validate(const FillPattern& f) {
  std::string problems;
  const auto need = [&problems](bool ok, const std::string& key, const std::string& what, double got) {
    if (ok) return;
    if (!problems.empty()) problems += "; ";
    problems += "fill " + key + " " + what + ", got " + std::to_string(got);
  };
  need(std::isfinite(f.angle_rad), "angle", "must be a number", f.angle_rad);
  need(f.bead_width_mm > 0 && std::isfinite(f.bead_width_mm), "bead width", "must be positive",
       f.bead_width_mm);
  need(f.overlap >= 0 && f.overlap < 1, "overlap", "must be in [0, 1)", f.overlap);
  need(f.max_overlap >= f.overlap && f.max_overlap < 1, "max overlap", "must be in [overlap, 1)",
       f.max_overlap);
  const std::pair<const char*, double> lengths[] = {
      {"max sparse spacing", f.max_sparse_spacing_mm}, {"min fill length", f.min_fill_length_mm},
      {"turn link max", f.turn_link_max_mm},           {"fillet radius", f.fillet_radius_mm},
      {"line extension", f.line_extension_mm},         {"line matching limit", f.line_matching_limit_mm}};
  for (const auto& [key, value] : lengths)
    need(value >= 0 && std::isfinite(value), key, "must be >= 0", value);
  if (!problems.empty()) throw InputError(problems);
}

// One fill line in the local frame (lines along +x): its printed runs, left to right, with their run-on.
struct Line {
  double y = 0;
  std::vector<Span> runs;
  Eigen::Vector2d start(int dir) const { return {dir > 0 ? runs.front().x0 : runs.back().x1, y}; }
};
using Group = std::vector<Line>;  // the lines of one cell, bottom to top

// The line at height `y` over `spans` (sorted), without those shorter than the minimum fill length; runs
// that their run-on makes meet are joined.
std::optional<Line> make_line(const std::vector<Span>& spans, double y, const FillPattern& f) {
  Line line{y, {}};
  const double ext = f.line_extension_mm;
  for (const Span& s : spans) {
    if (s.x1 - s.x0 < std::max(f.min_fill_length_mm, kMinLine)) continue;
    const Span run{s.x0 - ext, s.x1 + ext};
    if (!line.runs.empty() && run.x0 <= line.runs.back().x1)
      line.runs.back().x1 = std::max(line.runs.back().x1, run.x1);
    else
      line.runs.push_back(run);
  }
  if (line.runs.empty()) return std::nullopt;
  return line;
}

// Line heights at `pitch` across [y_min, y_max], centred so the leftover splits evenly on both sides.
std::vector<double> uniform_rows(double y_min, double y_max, double pitch) {
  const double span = y_max - y_min;
  const int count = static_cast<int>(std::floor(span / pitch + 1e-9)) + 1;
  const double first = y_min + 0.5 * (span - (count - 1) * pitch);
  std::vector<double> rows;
  for (int i = 0; i < count; ++i) rows.push_back(first + i * pitch);
  return rows;
}

// Whole cross-sections, gaps over holes included (one-way and simple zigzag).
Group whole_lines(const BoustrophedonCells& cells, const std::vector<double>& rows, const FillPattern& f) {
  Group lines;
  for (double y : rows)
    if (auto line = make_line(cells.cross_section(y), y, f)) lines.push_back(std::move(*line));
  return lines;
}

// Each cell's part of the rows whose index is `residue` modulo `every` (smart and sparse zigzag).
std::vector<Group> cell_lines(const BoustrophedonCells& cells, const std::vector<double>& rows,
                              const FillPattern& f, std::size_t every, std::size_t residue) {
  std::vector<Group> groups(cells.cells().size());
  for (std::size_t c = 0; c < groups.size(); ++c)
    for (std::size_t i = residue; i < rows.size(); i += every)
      if (cells.owns(c, rows[i]))
        if (auto line = make_line({cells.span(c, rows[i])}, rows[i], f))
          groups[c].push_back(std::move(*line));
  return groups;
}

// Heights dividing a cell's band evenly at a spacing in [min_pitch, pitch]; a line on an open end is the
// neighbour's. A band too narrow for that gets lines at `pitch`, centred, kept `min_pitch` from open ends.
std::vector<double> even_heights(const BoustrophedonCells::Cell& c, double pitch, double min_pitch) {
  const double band = c.y_hi - c.y_lo;
  const int n = std::max(1, static_cast<int>(std::ceil(band / pitch - 1e-9)));
  std::vector<double> ys;
  if (band / n >= min_pitch - 1e-12) {
    for (int j = 0; j <= n; ++j) {
      if ((j == 0 && !c.lo_closed) || (j == n && !c.hi_closed)) continue;
      ys.push_back(j == n ? c.y_hi : c.y_lo + j * band / n);
    }
    return ys;
  }
  const double lo = c.y_lo + (c.lo_closed ? 0 : min_pitch), hi = c.y_hi - (c.hi_closed ? 0 : min_pitch);
  if (hi < lo) return ys;
  for (double y : uniform_rows(lo, hi, pitch)) ys.push_back(y);
  return ys;
}

std::vector<Group> even_cell_lines(const BoustrophedonCells& cells, const FillPattern& f) {
  const double w = f.bead_width_mm;
  std::vector<Group> groups(cells.cells().size());
  for (std::size_t c = 0; c < groups.size(); ++c)
    for (double y : even_heights(cells.cells()[c], w * (1 - f.overlap), w * (1 - f.max_overlap)))
      if (auto line = make_line({cells.span(c, y)}, y, f)) groups[c].push_back(std::move(*line));
  return groups;
}

// A path under construction in the local frame: the start, then each vertex ends a segment with its flags.
struct Vertex {
  Eigen::Vector2d p;
  bool print = true;
  bool corner = false;
};
using LocalPath = std::vector<Vertex>;

// Lays lines into paths, linking them with printed turns where the pattern allows.
class Assembler {
 public:
  Assembler(const FillPattern& f, const Polygons& local_region) : f_(f) {
    const double w = f.bead_width_mm;
    const double reach = std::max(0.5 * w, f.line_extension_mm + (f.turns_outside ? 0.5 * w : 0.0));
    turn_region_ = offset(local_region, reach + kTurnSlack);
  }

  // FIG. 15: every line left to right, each its own path.
  void one_way(const Group& lines) {
    for (const Line& line : lines) {
      end_path();
      lay(line, +1, line.start(+1));
    }
    end_path();
  }

  // A serpentine through each group in turn, the next group the one whose first or last line starts
  // nearest the head; `spacing` between the lines linked (sets the default turn limit).
  void serpentine(const std::vector<Group>& groups, double spacing) {
    std::vector<bool> done(groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g) done[g] = groups[g].empty();
    for (;;) {
      const Eigen::Vector2d head = paths_.empty() ? lower_left(groups) : paths_.back().back().p;
      std::size_t best = groups.size();
      bool from_top = false;
      int dir = 1;
      double best_d = std::numeric_limits<double>::infinity();
      for (std::size_t g = 0; g < groups.size(); ++g) {
        if (done[g]) continue;
        for (const bool top : {false, true})
          for (const int d : {1, -1}) {
            const double dist = ((top ? groups[g].back() : groups[g].front()).start(d) - head).norm();
            if (dist < best_d - 1e-9) best_d = dist, best = g, from_top = top, dir = d;
          }
      }
      if (best == groups.size()) return;
      done[best] = true;
      lay_group(groups[best], from_top, dir, spacing);
    }
  }

  void end_path() { open_ = false; }
  // Whether consecutive lines may be linked by printed turns (the sparse style's gap passes may not).
  void set_linking(bool on) { linking_ = on; }
  std::vector<LocalPath>& paths() { return paths_; }

 private:
  static Eigen::Vector2d lower_left(const std::vector<Group>& groups) {
    Eigen::Vector2d p = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    for (const Group& g : groups)
      for (const Line& l : g) p = p.cwiseMin(l.start(+1));
    return p;
  }

  void lay_group(const Group& lines, bool from_top, int dir, double spacing) {
    const std::size_t n = lines.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Line& line = lines[from_top ? n - 1 - i : i];
      if (const auto from = turn_to(line, dir, spacing)) {
        lay(line, dir, *from);
      } else {
        // No turn: a new path, from whichever end of the line is nearer.
        if (i > 0) {
          const Eigen::Vector2d head = paths_.back().back().p;
          dir = (line.start(1) - head).norm() <= (line.start(-1) - head).norm() ? 1 : -1;
        }
        end_path();
        lay(line, dir, line.start(dir));
      }
      dir = -dir;
    }
  }

  // The line's runs in direction `dir`, the first one starting at `from`; gaps between runs are crossed
  // without printing.
  void lay(const Line& line, int dir, const Eigen::Vector2d& from) {
    if (!open_) paths_.push_back({Vertex{from, false, false}});
    LocalPath& path = paths_.back();
    const std::size_t n = line.runs.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Span& run = line.runs[dir > 0 ? k : n - 1 - k];
      if (k > 0) path.push_back({{dir > 0 ? run.x0 : run.x1, line.y}, false, false});
      path.push_back({{dir > 0 ? run.x1 : run.x0, line.y}, true, false});
    }
    open_ = true;
    dir_ = dir;
  }

  // A printed turn from the open path's end to the start of `next` (laid in direction `dir`): ends evened
  // (line matching), moved outside (turns outside), checked for length and for staying in the turn region.
  // Returns where `next` starts, or nothing if the lines are not to be linked.
  std::optional<Eigen::Vector2d> turn_to(const Line& next, int dir, double spacing) {
    if (!open_ || !linking_ || f_.link_with_rapids || dir != -dir_) return std::nullopt;
    LocalPath& path = paths_.back();
    const Eigen::Vector2d end = path.back().p, start = next.start(dir);
    Eigen::Vector2d e1 = end, e2 = start;
    const double out = dir_;  // outward along the lines at this side
    const double uneven = (e2.x() - e1.x()) * out;
    double slack = kTurnSlack;
    if (std::abs(uneven) > 1e-6 && f_.line_matching_limit_mm > 0) {
      if (std::abs(uneven) > f_.line_matching_limit_mm + 1e-9) return std::nullopt;
      // Patent (64): the shorter line is extended to be even with the longer; the bridge may stick out as
      // far as it was extended.
      if (uneven > 0)
        e1.x() = e2.x();
      else
        e2.x() = e1.x();
      slack += std::abs(uneven);
    }
    const double max_len = f_.turn_link_max_mm > 0 ? f_.turn_link_max_mm : 1.5 * spacing;
    const double shifts[] = {f_.turns_outside ? 0.5 * f_.bead_width_mm : 0.0, 0.0};
    for (const double shift : shifts) {
      const Eigen::Vector2d a = e1 + Eigen::Vector2d(out * shift, 0),
                            b = e2 + Eigen::Vector2d(out * shift, 0);
      if ((b - a).norm() > max_len + 1e-9) continue;
      if (outside_length({end, a, b, start}) > slack) continue;
      path.back().p = a;  // the line runs on to the turn
      path.push_back({b, true, true});
      return b;
    }
    return std::nullopt;
  }

  // Length of the polyline outside the turn region, mm.
  double outside_length(const Polyline& points) const {
    Polyline clean;
    for (const Eigen::Vector2d& p : points)
      if (clean.empty() || (p - clean.back()).norm() > 1e-9) clean.push_back(p);
    if (clean.size() < 2) return 0;
    double length = 0;
    for (const Polyline& piece : clip_lines({clean}, turn_region_, false))
      for (std::size_t i = 1; i < piece.size(); ++i) length += (piece[i] - piece[i - 1]).norm();
    return length;
  }

  const FillPattern& f_;
  Polygons turn_region_;
  std::vector<LocalPath> paths_;
  bool open_ = false;
  bool linking_ = true;
  int dir_ = 1;
};

// The corners at turns replaced by arcs of `radius` (less where the segments beside are too short: the arc
// takes at most half of each).
LocalPath fillet(const LocalPath& path, double radius) {
  if (radius <= 0 || path.size() < 3) return path;
  LocalPath out{path.front()};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vertex& v = path[i];
    if (i + 1 == path.size() || !v.print || !path[i + 1].print || !(v.corner || path[i + 1].corner)) {
      out.push_back(v);
      continue;
    }
    const Eigen::Vector2d in = v.p - path[i - 1].p, next = path[i + 1].p - v.p;
    const double len_in = in.norm(), len_out = next.norm();
    const double turn = len_in > kMinLine && len_out > kMinLine ? turn_rad(in, next) : 0.0;
    const double half_tan = std::tan(0.5 * std::abs(turn));
    if (std::abs(turn) < 1e-6 || std::abs(turn) > std::numbers::pi - 1e-3) {
      out.push_back(v);
      continue;
    }
    const double t = std::min({radius * half_tan, 0.5 * len_in, 0.5 * len_out});
    const double r = t / half_tan;
    const Eigen::Vector2d u = in / len_in;
    const Eigen::Vector2d t1 = v.p - t * u, t2 = v.p + t * next / len_out;
    const Eigen::Vector2d normal = turn > 0 ? Eigen::Vector2d(-u.y(), u.x()) : Eigen::Vector2d(u.y(), -u.x());
    const Eigen::Vector2d centre = t1 + r * normal;
    const int steps = std::max(
        1, static_cast<int>(std::ceil(std::abs(turn) / (0.5 * std::numbers::pi) * kArcSegmentsPerQuarter)));
    out.push_back({t1, v.print, v.corner});
    for (int k = 1; k < steps; ++k)
      out.push_back({centre + rotate(t1 - centre, turn * k / steps), true, true});
    out.push_back({t2, true, true});
  }
  return out;
}

// Sparse gap passes (paths from `first` on) end where the first serpentine turned: there they stop short,
// overlapping the turn's bead by the pass overlap instead of running over it, and those ends are not free.
// Returns (free start, free end) per path.
std::vector<std::pair<bool, bool>> trim_against_turns(std::vector<LocalPath>& paths, std::size_t first,
                                                      const FillPattern& f) {
  std::vector<std::pair<bool, bool>> free(paths.size(), {true, true});
  const double w = f.bead_width_mm, back = w * (0.5 - f.overlap);
  auto near_turn = [&](const Eigen::Vector2d& p) {
    for (std::size_t i = 0; i < first; ++i)
      for (std::size_t k = 1; k < paths[i].size(); ++k) {
        if (!paths[i][k].corner) continue;
        const Eigen::Vector2d a = paths[i][k - 1].p, d = paths[i][k].p - a;
        const double t = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
        if ((a + t * d - p).norm() < 0.5 * w) return true;
      }
    return false;
  };
  for (std::size_t i = first; i < paths.size(); ++i) {
    LocalPath& path = paths[i];
    if (path.size() < 2) continue;
    for (const bool at_end : {false, true}) {
      Vertex& v = at_end ? path.back() : path.front();
      const Vertex& inner = at_end ? path[path.size() - 2] : path[1];
      if (!near_turn(v.p)) continue;
      const Eigen::Vector2d d = inner.p - v.p;
      if (d.norm() <= back + kMinLine) continue;
      v.p += back * d.normalized();
      (at_end ? free[i].second : free[i].first) = false;
    }
  }
  return free;
}

std::vector<FillPath> to_global(const std::vector<LocalPath>& paths, const FillPattern& f,
                                const std::vector<std::pair<bool, bool>>& free = {}) {
  std::vector<FillPath> out;
  for (std::size_t n = 0; n < paths.size(); ++n) {
    const LocalPath path = fillet(paths[n], f.fillet_radius_mm);
    if (path.size() < 2) continue;
    FillPath fp{rotate(path.front().p, f.angle_rad), {}};
    if (n < free.size()) std::tie(fp.free_start, fp.free_end) = free[n];
    for (std::size_t i = 1; i < path.size(); ++i)
      fp.segments.push_back({rotate(path[i].p, f.angle_rad), path[i].print, path[i].corner});
    out.push_back(std::move(fp));
  }
  return out;
}

Polygons rotate(const Polygons& polys, double angle_rad) {
  Polygons out = polys;
  for (Polygon& poly : out)
    for (Eigen::Vector2d& p : poly) p = rotate(p, angle_rad);
  return out;
}

}  // namespace

std::vector<FillPath> plan_fill(const Polygons& region, const FillPattern& pattern) {
  validate(pattern);
  const Polygons local = rotate(region, -pattern.angle_rad);
  // A side stepping by less than half a bead stays in its cell: the bead covers most of the step anyway.
  const BoustrophedonCells cells(local, 0.5 * pattern.bead_width_mm);
  if (cells.cells().empty()) return {};
  const double pitch = pattern.bead_width_mm * (1 - pattern.overlap);
  const std::vector<double> rows = uniform_rows(cells.y_min(), cells.y_max(), pitch);
  Assembler a(pattern, local);
  switch (pattern.style) {
    case FillStyle::kOneWay:
      a.one_way(whole_lines(cells, rows, pattern));
      break;
    case FillStyle::kSimpleZigzag:
      a.serpentine({whole_lines(cells, rows, pattern)}, pitch);
      break;
    case FillStyle::kSmartZigzag:
      a.serpentine(cell_lines(cells, rows, pattern, 1, 0), pitch);
      break;
    case FillStyle::kSmartZigzagConstantOverlap:
      a.serpentine(even_cell_lines(cells, pattern), pitch);
      break;
    case FillStyle::kSparseZigzag: {
      // Every k-th row first; then each remaining residue, starting where the previous pass ended (so the
      // passes alternate their sweep direction).
      const double max_spacing =
          pattern.max_sparse_spacing_mm > 0 ? pattern.max_sparse_spacing_mm : 2 * pattern.bead_width_mm;
      const auto every = static_cast<std::size_t>(std::max(1.0, std::floor(max_spacing / pitch + 1e-9)));
      // The gap passes lie between beads already laid: a printed turn at their ends would run over the
      // first serpentine's turns, so each gap pass is a bead of its own.
      const std::size_t passes = pattern.sparse_fill_gaps ? every : 1;
      std::size_t first_phase = 0;
      for (std::size_t residue = 0; residue < passes; ++residue) {
        a.end_path();
        a.set_linking(residue == 0);
        a.serpentine(cell_lines(cells, rows, pattern, every, residue), static_cast<double>(every) * pitch);
        if (residue == 0) first_phase = a.paths().size();
      }
      const auto free = trim_against_turns(a.paths(), first_phase, pattern);
      return to_global(a.paths(), pattern, free);
    }
  }
  return to_global(a.paths(), pattern);
}

}  // namespace beadtwin::slicer
