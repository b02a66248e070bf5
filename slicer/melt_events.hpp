// Melt on and melt off settings (Thermwood patent, paragraphs (51)-(53); core/melt_settings.hpp): what the
// extruder does when a bead starts (prime) and when it ends (coast, reverse), applied to a planned toolpath.
//
// A planned bead is a melt-on dwell, its print moves, and a melt-off dwell (slicer/layer_builder.hpp).
// apply_melt_settings rewrites each bead by the settings of its section:
//
//   prime    At melt on the pump runs at the priming RPM for the prime time, so a blob of
//            flow_for_rpm(prime_rpm) · prime_time is laid where the bead starts: a kDwell move with event
//            and feature kPrime, that duration and that volume. Without the delay during priming the head
//            does not wait: the same volume is added on top of the bead's own to the first moves of the bead
//            that take the prime time at their commanded feed (a move is split where the prime time ends;
//            those moves carry event kPrime). Their flow is the bead's plus the priming flow. A bead
//            with no print time before its melt off takes the prime as the dwell.
//   coast    The melt off comes coast_distance before the bead's end (the move there is split) and the head
//            moves on through the coast distance with the pump off. The nozzle's pressure bleeds off
//            linearly with the distance coasted: the material per length falls from the bead's to zero over
//            the coast distance, so a coast lays half the bead's material over its length. The coast is
//            written as kCoastSteps moves of equal length (feature and event kCoast), each carrying the
//            exact integral of the linear decay over its length, so deposition sees the taper. A coast
//            longer than the bead's print moves covers the whole bead. The melt off before a coast does
//            not stop the head (time_toolpath).
//   reverse  The pump turns backwards at the reverse RPM, drawing material back from the nozzle: a kDwell
//            move with event and feature kReverse and volume 0 (nothing is laid; the drawn-back volume is
//            not booked, only the time). It comes after the melt off at the end of the bead, or, with reverse
//            during coast motion, at the start of the coast. With the delay during reverse the head waits for
//            the reverse time (the dwell's duration); without it the head moves on while the pump reverses
//            and the event is recorded with duration 0.
//   set at control
//            The controller supplies the prime and reverse times and RPMs (patent (53)). The prime and
//            reverse are recorded as dwells with the times given here, whatever the delay settings, as the
//            slicer's estimate; the program writer writes only the codes that start them
//            (gcode/writer.hpp).
//
// Toolpath::commanded_volume_mm3 stays the material commanded: the beads' own, plus the prime blobs, with
// the coasts' reduced material.
#pragma once

#include <vector>

#include "core/flow.hpp"
#include "core/melt_settings.hpp"
#include "core/toolpath.hpp"

namespace beadtwin::slicer {

// Coast moves written per coast (see the file comment).
inline constexpr int kCoastSteps = 4;

// Throws InputError (key "melt[<section>].<setting>") for a negative time, distance or RPM, or a prime or
// reverse RPM on an extruder that has none (a filament drive without a displacement).
void validate_melt_settings(const std::vector<MeltSettings>& per_section, const Extruder& extruder);

// Rewrites every bead of `tp` (melt-on dwell, moves, melt-off dwell) by the settings of its section
// (indexed by Move::section; a section without an entry, or moves without a section, keep the defaults:
// nothing changes). Call it on a planned toolpath before time_toolpath (the split moves need timing; the
// dwells keep the durations given here). Validates the extruder and the settings first. Throws
// InternalError when a melt on has no melt off after it.
void apply_melt_settings(Toolpath& tp, const std::vector<MeltSettings>& per_section,
                         const Extruder& extruder);

}  // namespace beadtwin::slicer
