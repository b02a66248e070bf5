// The Toolpath IR: the contract between every producer of motion (slicer, G-code reader) and
// every consumer (print-program writers, deposition, thermal, reports).
//
// A toolpath is a flat sequence of straight moves in the machine frame (mm). Arcs are linearised within
// the chord tolerance by whoever produces them. Every move keeps where it came from (section, layer,
// feature, boundary pass, source line), so any defect found downstream can be traced back.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace beadtwin {

enum class MoveKind : std::uint8_t {
  kPrint,   // material flows while the head moves
  kTravel,  // no flow (rapid or linking move)
  kDwell,   // head stands still for duration_s (may carry flow: prime, ooze)
};

// What the move is for, as the patent names the toolpath features.
enum class Feature : std::uint8_t {
  kUnknown,
  kTravel,
  kRaft,
  kBoundary,  // boundary pass `pass` (0 = outermost)
  kFill,
  kLeadIn,
  kLeadOut,
  kCoast,
  kStockOnTop,
  kThinWall,  // one bead down the centre of a wall too narrow for the boundary passes
  kPrime,
  kReverse,
};

// Extruder events are moves too, so nothing is lost between producer and consumer.
enum class ExtruderEvent : std::uint8_t {
  kNone,
  kMeltOn,
  kMeltOff,
  kPrime,
  kCoast,
  kReverse,
  kHeatOn,
  kHeatOff
};

std::string_view to_string(MoveKind kind);
std::string_view to_string(Feature feature);
std::string_view to_string(ExtruderEvent event);

// One straight move of the head, with what it lays and where it came from.
struct Move {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  // mm; z is the top of the bead being laid
  Eigen::Vector3d end = Eigen::Vector3d::Zero();    // mm
  MoveKind kind = MoveKind::kTravel;
  ExtruderEvent event = ExtruderEvent::kNone;
  Feature feature = Feature::kUnknown;
  bool roller_down = false;  // compression roller (or tamper) engaged
  float fan =
      0.0f;  // the part-cooling fan's (or air knife's) output while the move runs, 0 (off) to 1 (full)
  // The hot end's set temperature the program commanded before the move (M104/M109 S), °C; NaN where it
  // commanded none, and the material's deposition temperature stands for the bead's.
  float nozzle_c = std::numeric_limits<float>::quiet_NaN();
  double feed_mm_s = 0.0;        // commanded speed
  double volume_mm3 = 0.0;       // material the move extrudes (0 for travel): the commanded volume
  double bead_width_mm = 0.0;    // intended flattened width
  double layer_height_mm = 0.0;  // intended flattened height
  double start_s = 0.0;          // absolute time the move starts (set by the motion model)
  double duration_s = 0.0;       // set by the motion model (or given, for dwells)
  int section = -1;              // index into Toolpath::sections; -1 when unknown
  int layer = -1;                // index into Toolpath::layers; -1 when unknown
  int pass = -1;                 // boundary pass number, 0 = outermost; -1 otherwise
  int source_line = 0;           // line in the G-code program it came from; 0 when generated

  double length_mm() const { return (end - start).norm(); }
  // Mean volumetric flow over the move, mm³/s (0 for an instantaneous move).
  double flow_mm3_s() const { return duration_s > 0.0 ? volume_mm3 / duration_s : 0.0; }
  bool deposits() const { return volume_mm3 > 0.0; }
};

// One layer of a toolpath: its height and the range of moves and time it spans.
struct ToolpathLayer {
  double z_mm = 0.0;       // top of the layer
  double height_mm = 0.0;  // nominal layer height
  int section = -1;
  std::size_t first_move = 0;  // [first_move, end_move) in Toolpath::moves
  std::size_t end_move = 0;
  double start_s = 0.0;  // time of the layer's first deposit
  double end_s = 0.0;    // time of the layer's last deposit
  // The region the layer fills as the slicer saw it (0 when unknown, e.g. read from G-code).
  double outline_area_mm2 = 0.0;
  double outline_perimeter_mm = 0.0;
  double duration_s() const { return end_s - start_s; }
};

// A whole print's moves in order, with its layers and the names of its sections.
struct Toolpath {
  std::vector<std::string> sections;
  std::vector<ToolpathLayer> layers;
  std::vector<Move> moves;
  // Rotary axes A, B, C (degrees) at the end of each move, parallel to `moves`; empty when no rotary axis
  // moves (a 3-axis program). Read from programs and kept with the moves; timing and deposition follow the
  // tool's X, Y, Z alone.
  std::vector<Eigen::Vector3f> rotary_deg;

  double commanded_volume_mm3() const;  // material of every move, mm³
  double print_length_mm() const;       // path length of the print moves, mm
  double travel_length_mm() const;      // path length of the travel moves, mm
  double total_time_s() const;          // end of the last move, s (0 without moves); once timed

  // Fills layers[].first_move/end_move/start_s/end_s from the moves' layer indices and times.
  // Moves must be ordered so that each layer's moves are contiguous. Throws InternalError otherwise.
  void index_layers();
};

// Acceleration-limited timing (trapezoidal velocity profiles with a junction-deviation corner model, as
// motion controllers plan them). Sets start_s and duration_s of every move; dwells keep their duration.
// Instantaneous events (dwells of no duration) stop the head, except between a print move and the coast after
// it (the pump stops, the head moves on).
struct MotionLimits {
  double max_feed_mm_s = 500.0;
  double max_travel_mm_s = 500.0;
  double acceleration_mm_s2 = 1000.0;
  double junction_deviation_mm = 0.5;  // corner rounding the controller allows; sets cornering speed
};
void time_toolpath(Toolpath& toolpath, const MotionLimits& limits);
// The total time time_toolpath would find (Toolpath::total_time_s after it), leaving the toolpath as it is.
double motion_time_s(const Toolpath& toolpath, const MotionLimits& limits);

}  // namespace beadtwin
