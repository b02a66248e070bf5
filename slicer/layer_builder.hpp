// Writes one layer's moves into a Toolpath: travels (with the clearance height), melt events, and printed
// segments with their section, layer, feature and pass, the bead section and the flow. Every planner of a
// layer's beads (boundary passes, fill, thin walls) lays them through one LayerBuilder.
#pragma once

#include <algorithm>

#include "core/bead.hpp"
#include "core/toolpath.hpp"
#include "slicer/plan.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

// Lays one layer of one section; `head` (mm, in plan) follows the head from layer to layer.
class LayerBuilder {
 public:
  // `role` marks every printed move of the layer (kRaft, kStockOnTop); kUnknown keeps each move's own.
  LayerBuilder(Toolpath& tp, const SectionParams& s, int section, int layer, double z, Eigen::Vector2d& head,
               Feature role)
      : tp_(tp), s_(s), section_(section), layer_(layer), z_(z), head_(head), role_(role) {
    area_ = bead_area_mm2(s.bead_width_mm, s.layer_height_mm);
  }

  // Travels to `p` (mm) at the layer's height: across at the head's height first when it is above the layer.
  void travel_to(const Eigen::Vector2d& p) {
    Move m = base(Feature::kTravel);
    m.kind = MoveKind::kTravel;
    // From wherever the head really is (the previous layer's height on a layer change).
    // The program starts with the head at the initial clearance height (patent (45)), if one is set.
    m.start = tp_.moves.empty()
                  ? Eigen::Vector3d(head_.x(), head_.y(), std::max(z_, s_.initial_clearance_height_mm))
                  : tp_.moves.back().end;
    m.feed_mm_s = s_.travel_speed_mm_s;
    if (m.start.z() > z_ + 1e-9 && (p - m.start.head<2>()).norm() > 1e-9) {
      // Raised (clearance height): across at that height first, then straight down.
      m.end = {p.x(), p.y(), m.start.z()};
      tp_.moves.push_back(m);
      m.start = m.end;
    }
    m.end = {p.x(), p.y(), z_};
    head_ = p;
    if ((m.end - m.start).norm() < 1e-9) return;
    tp_.moves.push_back(m);
  }

  // An extruder event where the head stands, as a dwell (timed later by the melt settings).
  void event(ExtruderEvent e) {
    // A bead runs from melt on to melt off; its corners get the pull-back when it ends.
    if (e == ExtruderEvent::kMeltOff && s_.pull_back.length_mm + s_.pull_back.extension_mm > 0)
      pull_back_corners(tp_.moves, bead_start_, s_.pull_back);
    Move m = base(Feature::kUnknown);
    m.kind = MoveKind::kDwell;
    m.event = e;
    m.start = m.end = {head_.x(), head_.y(), z_};
    tp_.moves.push_back(m);
    if (e == ExtruderEvent::kMeltOn) bead_start_ = tp_.moves.size();
  }

  // Corner pull-back (patent (47)) on the print moves from `first` on: at every turn of at least the
  // minimum angle the roller lifts `length_mm` before the corner and re-engages `extension_mm` after it
  // (moves are split there; material stays with the length it belongs to).
  static void pull_back_corners(std::vector<Move>& moves, std::size_t first, const PullBackParams& p);

  // A closed boundary pass with its lead-in (a straight approach along the first segment's line, ending at
  // the start) and lead-out (a straight run-off along the last segment's direction), both printed.
  // `overlap_mm` runs the pass on past its start (start/stop overlap) before the lead-out.
  void print_pass(const Polygon& loop, int pass, double lead_in_mm, double lead_out_mm, double overlap_mm,
                  bool tangential_lead_out) {
    if (loop.size() < 2) return;
    const Eigen::Vector2d first_dir = (loop[1] - loop[0]).normalized();
    travel_to(loop.front() - lead_in_mm * first_dir);
    event(ExtruderEvent::kMeltOn);
    if (lead_in_mm > 0) print_segment(loop.front(), Feature::kLeadIn, pass);
    for (std::size_t i = 1; i <= loop.size(); ++i)
      print_segment(loop[i % loop.size()], Feature::kBoundary, pass);
    // Start/stop overlap, then (unless the lead-out is tangential) the lead-out: on along the contour again,
    // retracing the bead just laid, so the pump slows by the melt setting (patent (46)).
    const double flow = 1.0 - s_.melt_reduction;
    const std::size_t next = run_along(loop, 1, overlap_mm, Feature::kBoundary, pass, flow);
    if (!tangential_lead_out) run_along(loop, next, lead_out_mm, Feature::kLeadOut, pass, flow);
    if (tangential_lead_out) lead_out(lead_out_mm, true);
    event(ExtruderEvent::kMeltOff);
  }

  // Prints on along the closed `loop` from the head, which lies on the segment ending at loop[next], for
  // `length_mm`; returns the index of the next corner ahead.
  std::size_t run_along(const Polygon& loop, std::size_t next, double length_mm, Feature feature, int pass,
                        double flow) {
    // A bound on the laps, in case the loop is (nearly) a point.
    for (std::size_t guard = 0; length_mm > 1e-9 && guard < 4 * loop.size(); ++guard) {
      const Eigen::Vector2d to = loop[next % loop.size()];
      const double len = (to - head_).norm();
      if (len > length_mm) {
        print_segment(head_ + (to - head_) * (length_mm / len), feature, pass, flow);
        break;
      }
      print_segment(to, feature, pass, flow);
      length_mm -= len;
      next = (next + 1) % loop.size();
    }
    return next;
  }

  // An open path (AM Outline) with its lead-in along the first segment and its lead-out along the last.
  void print_open(const Polyline& path, int pass, double lead_in_mm, double lead_out_mm) {
    if (path.size() < 2) return;
    const Eigen::Vector2d first_dir = (path[1] - path[0]).normalized();
    travel_to(path.front() - lead_in_mm * first_dir);
    event(ExtruderEvent::kMeltOn);
    if (lead_in_mm > 0) print_segment(path.front(), Feature::kLeadIn, pass);
    for (std::size_t i = 1; i < path.size(); ++i) print_segment(path[i], Feature::kBoundary, pass);
    lead_out(lead_out_mm, true);
    event(ExtruderEvent::kMeltOff);
  }

  // A printed lead-out after the bead just laid: straight on along its last move (tangential), or back
  // along that move over the bead just laid (the pump slowed by the melt setting).
  void lead_out(double length_mm, bool tangential) {
    if (length_mm <= 0 || tp_.moves.empty() || tp_.moves.back().kind != MoveKind::kPrint) return;
    const Move last = tp_.moves.back();
    const Eigen::Vector2d d = (last.end - last.start).head<2>().normalized();
    if (tangential)
      print_segment(head_ + length_mm * d, Feature::kLeadOut, last.pass);
    else
      print_segment(head_ - std::min(length_mm, last.length_mm()) * d, Feature::kLeadOut, last.pass,
                    1.0 - s_.melt_reduction);
  }

  // One bead of its own width (a thin wall's); at least as wide as the layer is high.
  void print_thin(const Eigen::Vector2d& to, double width_mm, Feature feature = Feature::kThinWall) {
    const double w = std::max(width_mm, s_.layer_height_mm);
    const std::size_t before = tp_.moves.size();
    print_segment(to, feature, -1, bead_area_mm2(w, s_.layer_height_mm) / area_);
    if (tp_.moves.size() > before) tp_.moves.back().bead_width_mm = w;
  }

  // A print move of the section's bead from the head to `to` (mm); none shorter than 1 µm.
  // `flow` scales the material (the melt setting's pump reduction where a bead is laid over another, or the
  // fill's corner reduction); `feed_mm_s` > 0 replaces the print speed (the fill's corner speed).
  void print_segment(const Eigen::Vector2d& to, Feature feature, int pass, double flow = 1.0,
                     double feed_mm_s = 0.0) {
    const double len = (to - head_).norm();
    if (len < 1e-6) return;
    Move m = base(feature);
    m.kind = MoveKind::kPrint;
    m.pass = pass;
    m.roller_down = true;
    m.start = {head_.x(), head_.y(), z_};
    m.end = {to.x(), to.y(), z_};
    m.feed_mm_s = feed_mm_s > 0 ? feed_mm_s : s_.print_speed_mm_s;
    m.volume_mm3 = area_ * len * flow;
    tp_.moves.push_back(m);
    head_ = to;
  }

  const Eigen::Vector2d& head() const { return head_; }

 private:
  Move base(Feature feature) const {
    Move m;
    m.feature = role_ != Feature::kUnknown && feature != Feature::kTravel && feature != Feature::kUnknown
                    ? role_
                    : feature;
    m.section = section_;
    m.layer = layer_;
    m.bead_width_mm = s_.bead_width_mm;
    m.layer_height_mm = s_.layer_height_mm;
    return m;
  }

  Toolpath& tp_;
  const SectionParams& s_;
  int section_, layer_;
  double z_;
  Eigen::Vector2d& head_;
  Feature role_;
  double area_ = 0.0;
  std::size_t bead_start_ = 0;
};

// Rotates a closed contour so it starts at the point nearest `near`, moved `advance_mm` further along the
// contour in its own direction (the seam avoidance offset); the start becomes a vertex if it is not one.
// With `corner_clear_mm` > 0 (never start in a corner, patent (47)) the start moves on until it is at
// least that far from every corner.
Polygon start_at(const Polygon& poly, const Eigen::Vector2d& near, double advance_mm,
                 double corner_clear_mm = 0.0);

// Minimum polygon angle (patent (47)): corners of the material whose interior angle is below
// `min_interior_deg` are cut back by `cut_mm` along both edges, so the bead never turns that sharply.
Polygon blunt_corners(const Polygon& loop, double min_interior_deg, double cut_mm);

}  // namespace beadtwin::slicer
