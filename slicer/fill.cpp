#include "slicer/fill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.hpp"

namespace beadtwin::slicer {

namespace {

FillStyle style_for(FillStyleKind k, bool solid) {
  switch (k) {
    case FillStyleKind::kOneWay:
      return FillStyle::kOneWay;
    case FillStyleKind::kSimpleZigzag:
      return FillStyle::kSimpleZigzag;
    case FillStyleKind::kSmartZigzagConstantOverlap:
      return FillStyle::kSmartZigzagConstantOverlap;
    case FillStyleKind::kSparseZigzag:
      return solid ? FillStyle::kSmartZigzag : FillStyle::kSparseZigzag;
    case FillStyleKind::kSmartZigzag:
    case FillStyleKind::kVariableBeadRegions:
      return FillStyle::kSmartZigzag;
  }
  return FillStyle::kSmartZigzag;
}

// Runs the free ends of a path on along their passes by `by`: the path's own start and end, and the ends
// beside a hole it crosses without depositing (they meet the passes around the hole). Ends that turn into
// the next pass stay where they are: the turn runs beside the boundary.
void extend_free_ends(FillPath& path, double by) {
  auto& seg = path.segments;
  if (by <= 0 || seg.empty()) return;
  auto from = [&](std::size_t i) { return i == 0 ? path.start : seg[i - 1].to; };
  auto dir = [&](std::size_t i) -> Eigen::Vector2d {
    const Eigen::Vector2d d = seg[i].to - from(i);
    return d.norm() > 1e-9 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d::Zero();
  };
  std::vector<Eigen::Vector2d> ends(seg.size());  // new end of each segment
  for (std::size_t i = 0; i < seg.size(); ++i) ends[i] = seg[i].to;
  Eigen::Vector2d start = path.start;
  for (std::size_t i = 0; i < seg.size(); ++i) {
    if (!seg[i].print) continue;
    const bool free_start = i == 0 ? path.free_start : !seg[i - 1].print;
    const bool free_end = i + 1 == seg.size() ? path.free_end : !seg[i + 1].print;
    if (free_start) (i == 0 ? start : ends[i - 1]) -= by * dir(i);
    if (free_end) ends[i] += by * dir(i);
  }
  path.start = start;
  for (std::size_t i = 0; i < seg.size(); ++i) seg[i].to = ends[i];
}

}  // namespace

FillRegions fill_regions(const SectionParams& s, const Polygons& host, int passes_laid) {
  const FillParams& f = s.fill;
  const double w = s.bead_width_mm;
  FillRegions out;
  if (passes_laid == 0) {
    // No boundary: bead centres half a bead inside the outline, ends out to it.
    out.centres = offset(host, -0.5 * w);
    out.end_reach_mm = 0.5 * w;
    return out;
  }
  // The boundary beads' inner edge, then the sides' overlap with it and how far pass ends reach into it.
  const double pitch = w * (1.0 - s.boundary.overlap);
  const double inner = w + (passes_laid - 1) * pitch;
  double side = f.boundary_side_overlap * w;
  if (f.max_side_overlap_mm > 0) side = std::min(side, f.max_side_overlap_mm);
  double end =
      f.optimize_to_surface ? (f.max_end_overlap_mm > 0 ? f.max_end_overlap_mm : w) : f.boundary_overlap * w;
  if (f.max_end_overlap_mm > 0) end = std::min(end, f.max_end_overlap_mm);
  out.centres = offset(host, -(inner + 0.5 * w - side));
  out.end_reach_mm = 0.5 * w - side + end;
  return out;
}

int lay_fill(LayerBuilder& b, const SectionParams& s, const FillRegions& regions, int layer_in_section,
             bool solid) {
  const FillParams& f = s.fill;
  if (regions.centres.empty()) return 0;
  FillPattern p;
  p.style = style_for(f.style, solid);
  p.angle_rad = (f.angle_deg + layer_in_section * f.angle_step_deg) * kPi / 180.0;
  p.bead_width_mm = s.bead_width_mm;
  p.overlap = f.overlap;
  p.max_overlap = f.max_overlap;
  p.max_sparse_spacing_mm = f.max_sparse_spacing_mm;
  p.sparse_fill_gaps = f.sparse_fill_gaps;
  p.min_fill_length_mm = f.min_length_mm;
  p.link_with_rapids = f.link_with_rapids;
  p.fillet_radius_mm = f.fillet_radius * 0.5 * s.bead_width_mm;
  p.turns_outside = f.turns_outside;
  p.line_extension_mm = f.line_extension_mm;
  p.line_matching_limit_mm = f.line_matching_limit_mm;
  const double corner_flow = 1.0 - f.corner_melt_reduction;
  int beads = 0;
  for (FillPath path : plan_fill(regions.centres, p)) {
    if (path.segments.empty()) continue;
    // Free ends (the path's own, and those beside a hole it crosses) reach into the boundary beads; ends
    // that turn into the next pass stay where they are (the turn runs beside the boundary).
    extend_free_ends(path, regions.end_reach_mm);
    const Eigen::Vector2d first_dir = (path.segments.front().to - path.start).normalized();
    b.travel_to(path.start - f.lead_in_mm * first_dir);
    b.event(ExtruderEvent::kMeltOn);
    ++beads;
    if (f.lead_in_mm > 0) b.print_segment(path.start, Feature::kLeadIn, -1);
    bool melting = true;
    for (const FillSegment& seg : path.segments) {
      if (!seg.print) {
        // Over a hole: stop depositing, cross, resume (patent (58)).
        if (melting) b.event(ExtruderEvent::kMeltOff);
        melting = false;
        b.travel_to(seg.to);
        continue;
      }
      if (!melting) {
        b.event(ExtruderEvent::kMeltOn);
        ++beads;
        melting = true;
      }
      b.print_segment(seg.to, Feature::kFill, -1, seg.corner ? corner_flow : 1.0,
                      seg.corner ? f.corner_speed_mm_s : 0.0);
    }
    if (melting && f.lead_out_mm > 0) b.lead_out(f.lead_out_mm, f.tangential_lead_out);
    if (melting) b.event(ExtruderEvent::kMeltOff);
  }
  return beads;
}

}  // namespace beadtwin::slicer
