// Melt on and melt off settings (Thermwood patent, paragraphs (51)-(53)): what the extruder does when a bead
// starts (prime) and when it ends (coast, reverse), per section of a part.
//
// The planner applies them to its beads (slicer/melt_events.hpp says how); the program writer writes the
// codes, speeds and dwells they ask for (gcode/writer.hpp). Both read this one struct.
#pragma once

namespace beadtwin {

// One section's melt on / melt off settings (patent (51)-(53)). Times in s, distances in mm, speeds in
// rev/min.
struct MeltSettings {
  bool prime = false;                 // prime melt when turning on (51)
  bool delay_during_prime = true;     // the head waits at the bead's start while priming (51)
  double prime_time_s = 0;            // how long the prime runs (51)
  double prime_rpm = 0;               // pump or screw speed while priming (51)
  bool coast = false;                 // apply coast off motion (52)
  double coast_distance_mm = 0;       // distance before the bead's end at which the pump stops (52)
  bool reverse = false;               // reverse melt when turning off (52)
  bool reverse_during_coast = false;  // the reverse starts with the coast instead of at the bead's end (53)
  bool delay_during_reverse = true;   // the head waits for the reverse time (53)
  double reverse_time_s = 0;          // how long the pump reverses (53)
  double reverse_rpm = 0;             // pump or screw speed while reversing (53)
  bool set_at_control = false;        // prime and reverse times and RPMs come from the controller (53)
};

}  // namespace beadtwin
