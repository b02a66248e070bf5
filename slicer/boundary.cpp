#include "slicer/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "slicer/centre_beads.hpp"

namespace beadtwin::slicer {
namespace {

// Clipping a closed ring cuts it at its first point too: pieces that meet end to end are one pass again.
std::vector<Polyline> join_pieces(std::vector<Polyline> pieces) {
  for (bool joined = true; joined;) {
    joined = false;
    for (std::size_t i = 0; i < pieces.size() && !joined; ++i)
      for (std::size_t j = 0; j < pieces.size() && !joined; ++j) {
        if (i == j || (pieces[i].back() - pieces[j].front()).norm() > 1e-6) continue;
        pieces[i].insert(pieces[i].end(), pieces[j].begin() + 1, pieces[j].end());
        pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(j));
        joined = true;
      }
  }
  return pieces;
}

}  // namespace

BoundaryPlan plan_boundary(const SectionParams& s, const Polygons& region, const Polygons& shared_wall,
                           bool fill) {
  const double w = s.bead_width_mm;
  const double pitch = w * (1.0 - s.boundary.overlap);
  Polygons host = region, keep_out;
  if (!shared_wall.empty()) {
    // The two sections as one region (a closing bridges a seam narrower than w/2 between them); pass pieces
    // end overlap·w deep in the neighbour, on the bead its wall lays there.
    const double g = 0.25 * w;
    host = offset(offset(unite(region, shared_wall), g), -g);
    keep_out = offset(shared_wall, -s.boundary.overlap * w);
  }
  // Where a pass's own sides come closer than w·(1 − max overlap) the pass is opened away.
  const double open_by = s.boundary.max_overlap < 1.0 ? 0.5 * w * (1.0 - s.boundary.max_overlap) : 0.0;
  auto centres = [&](int k) {
    Polygons r = offset(host, -(0.5 * w + k * pitch));
    return open_by > 0 ? offset(offset(r, -open_by), open_by) : r;
  };
  BoundaryPlan plan;
  plan.reach = offset(centres(0), 0.5 * w);
  for (int k = 0; k < s.boundary.passes; ++k) {
    Polygons loops = centres(k);
    if (loops.empty()) break;
    if (s.smoothing.min_polygon_angle_deg > 0)
      for (Polygon& loop : loops) loop = blunt_corners(loop, s.smoothing.min_polygon_angle_deg, 0.5 * w);
    Polygons closed;
    std::vector<Polyline> open;
    for (const Polygon& loop : loops) {
      Polyline ring = loop;
      ring.push_back(loop.front());
      if (keep_out.empty() || clip_lines({ring}, keep_out, true).empty()) {
        closed.push_back(loop);
        continue;
      }
      for (Polyline& piece : join_pieces(clip_lines({ring}, keep_out, false)))
        open.push_back(std::move(piece));
    }
    plan.loops.push_back(std::move(closed));
    plan.pieces.push_back(std::move(open));
  }
  if (fill) {
    plan.fill = fill_regions(s, host, static_cast<int>(plan.loops.size()));
    // Against a shared wall the fill's sides stop where they would beside a boundary bead of its own.
    if (!shared_wall.empty())
      plan.fill.centres =
          difference(plan.fill.centres, offset(shared_wall, 0.5 * w - s.fill.boundary_side_overlap * w));
  }
  return plan;
}

void lay_boundary(LayerBuilder& b, const SectionParams& s, const BoundaryPlan& plan, int layer_in_section) {
  const int laid = static_cast<int>(plan.loops.size());
  const bool reversed = s.boundary.reverse_alternate && layer_in_section % 2 == 1;
  const double advance = layer_in_section * s.seam_offset_mm;
  const double corner_clear = s.smoothing.never_start_in_corner ? s.bead_width_mm : 0.0;
  for (int i = 0; i < laid; ++i) {
    const auto k = static_cast<std::size_t>(s.boundary.inside_out ? laid - 1 - i : i);
    for (Polygon loop : plan.loops[k]) {
      if (s.boundary.min_pass_length_mm > 0 && perimeter_mm({loop}) < s.boundary.min_pass_length_mm) continue;
      if (reversed) std::reverse(loop.begin(), loop.end());
      b.print_pass(start_at(loop, s.start_point_mm, advance, corner_clear), static_cast<int>(k),
                   s.boundary.lead_in_mm, s.boundary.lead_out_mm,
                   s.boundary.start_stop_overlap * s.bead_width_mm, s.boundary.tangential_lead_out);
    }
    // Pieces ending against a shared wall: no lead-in or lead-out (they would print into the neighbour).
    for (Polyline piece : plan.pieces[k]) {
      double length = 0.0;
      for (std::size_t j = 1; j < piece.size(); ++j) length += (piece[j] - piece[j - 1]).norm();
      if (length < std::max(s.boundary.min_pass_length_mm, 1e-6)) continue;
      const bool from_far_end =
          (piece.back() - s.start_point_mm).norm() < (piece.front() - s.start_point_mm).norm();
      if (from_far_end != reversed) std::reverse(piece.begin(), piece.end());
      b.print_open(piece, static_cast<int>(k), 0.0, 0.0);
    }
  }
}

CentreBeadRules thin_wall_rules(const SectionParams& s) {
  const double w = s.bead_width_mm;
  CentreBeadRules r;
  r.min_width_mm = 0.1 * w;
  r.max_width_mm = s.boundary.thin_wall_max_width_mm > 0 ? s.boundary.thin_wall_max_width_mm : w;
  r.one_bead_width_mm =
      s.boundary.thin_wall_one_bead_width_mm > 0 ? s.boundary.thin_wall_one_bead_width_mm : w;
  r.thickness_deviation_mm = s.boundary.thin_wall_thickness_deviation_mm;
  r.stitching_gap_mm = s.boundary.thin_wall_stitching_gap_mm;
  r.intersection_distance_mm = s.boundary.thin_wall_intersection_distance_mm;
  return r;
}

void lay_thin_walls(LayerBuilder& b, const SectionParams& s, const Polygons& region,
                    const BoundaryPlan& plan) {
  // What the outer pass cannot reach, less the numerical slivers along edges the offsets do not quite
  // restore (a small opening, a tenth of the bead: anything that narrow cannot take a bead anyway).
  const double sliver = 0.1 * s.bead_width_mm;
  const Polygons thin = offset(offset(difference(region, plan.reach), -sliver), sliver);
  lay_centre_beads(b, centre_beads(thin, plan.reach, thin_wall_rules(s)), Feature::kThinWall);
}

}  // namespace beadtwin::slicer
