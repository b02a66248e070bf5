// Reading G-code programs into the Toolpath IR (core/toolpath.hpp): a program from any slicer, or one of
// our own (gcode/writer.hpp), becomes the moves, layers and extruder events the simulation runs on.
//
// The block reader consumes Blocks (gcode/block.hpp) one at a time, from the plain lexer (gcode/lexer.hpp)
// or from the macro interpreter (gcode/macro.hpp); read_gcode (gcode/program_reader.hpp) feeds it a whole
// program. It keeps only the Toolpath it builds: memory grows with the moves, not with the program's text.
//
// What the blocks mean:
//   motion     G0 is travel, at ReaderOptions::rapid_feed_mm_s where the controller runs G0 at its rapid
//              traverse (CNC controllers), else at the programmed F (Marlin). G1, G2 and G3 print when
//              material flows: the E word grows (filament machines),
//              or, without an E word, the melt is on and the pump turns (pump machines; the speed word,
//              S or ReaderOptions::rpm_word, is its speed in rev/min, turned into flow by
//              ReaderOptions::extruder; a filament drive with a
//              constant feed, Extruder::constant_feed_mm_s, feeds Q = π d_f² v_e / 4 from melt on to melt
//              off, as on the hybrid machine of seed 002). G2/G3 take I/J/K centre
//              offsets (from the start) or R (negative: the longer arc) in the plane of G17 (XY), G18 (ZX)
//              or G19 (YZ), start == end with I/J/K being a full circle, the third axis moving along (a
//              helix), P the number of turns; they become straight moves within the chord tolerance
//              (gcode/arc.hpp). A, B and C (rotary axes) are read and left out of the motion, with
//              a warning.
//   modes      G20/G21 inch/mm, G90/G91 absolute/relative (E too, as Marlin does), M82/M83 absolute/relative
//              E, G92 sets the position (axes shift the program's origin, E restarts), G28 homes to 0,
//              M200 D<d> turns volumetric E on with filament diameter d (D0 off; as Marlin and RepRapFirmware
//              read it), F is per minute (in/min under G20).
//   dwells     G4 P (milliseconds, or seconds with ReaderOptions::dwell_p_seconds), S or X (seconds).
//   material   A print move's volume is the E it feeds times the filament's section (or E itself when
//              volumetric), or the pump's (or constant feed's) flow times the move's duration at its feed
//              (length / feed): the slower the head, the wider the bead (seed 002 eq. 12). E drawn
//              back (a retraction: E falling without motion) is owed; E fed again first refills the nozzle
//              (ReaderOptions::refill_after_retract), only what exceeds the debt is laid.
//   beads      The section A = volume / length and the layer height h give the width through the stadium of
//              core/bead.hpp; a section below π h²/4 is a round bead of diameter √(4 A / π) (width and height
//              both that). Slicer annotations WIDTH: and HEIGHT: are used instead when present.
//   layers     A layer starts when material is laid at a new Z (Z hops without material start none). Its
//              height is its Z less the previous layer's (the first layer's: its Z) unless a HEIGHT
//              annotation says otherwise. Moves without material just before, at the new Z (the travel
//              there, a melt on, an unretract), belong to the new layer. Layer markers in comments are
//              counted and checked against the layers found. (gcode/annotations.hpp)
//   events     Melt on/off codes (ReaderOptions) become kMeltOn/kMeltOff dwells of no duration (only when
//              the state changes); heat on/off kHeatOn/kHeatOff; roller codes set Move::roller_down; the
//              prime code and reverse codes give kPrime and kReverse dwells, timed by the G4 after them. A
//              retraction in place is a kReverse dwell, feeding E in place (unretract, prime) a kPrime dwell
//              carrying the material laid, each lasting its E length over its feed. A dwell while the pump
//              turns lays material: a kPrime dwell.
//   features   From TYPE: and region comments (gcode/annotations.hpp), else kUnknown; travel and
//              events are kTravel, prime and reverse dwells kPrime and kReverse.
//   the end    M2 or M30 ends the program: later blocks are ignored.
//
// Bad input: a number that is not finite, a coordinate beyond ReaderOptions::max_coordinate_mm, a negative
// feed or speed, an arc without centre or with a radius too short for its chord, more moves than
// ReaderOptions::max_moves: InputError naming file, line and column (key "gcode"). Words or codes the
// reader does not know, words no code in their block uses, rotary axes, tool changes and the like are
// warnings: counted per kind in ReadStats, the first of each kind kept as a message, never more than
// ReaderOptions::max_messages of them.
//
// The toolpath has one section, named after the file. Moves carry their source line. Times are left to
// the motion model (time_toolpath), except the dwells' durations.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/toolpath.hpp"
#include "gcode/block.hpp"
#include "gcode/reader_options.hpp"

namespace beadtwin::gcode {

// What reading a program met, for the user: counts and the warnings by kind.
struct ReadStats {
  std::size_t lines = 0;                        // lines read (read_gcode)
  std::size_t blocks = 0;                       // blocks fed to the reader
  std::size_t deleted_blocks = 0;               // skipped by block delete
  std::size_t arcs = 0;                         // G2/G3 blocks linearised
  std::size_t moves = 0;                        // moves in the toolpath
  std::size_t layer_markers = 0;                // layer change comments seen
  bool ended = false;                           // M2 or M30 ended the program
  std::map<std::string, std::size_t> warnings;  // how often each kind of warning came up
  std::vector<std::string> messages;  // the first warning of each kind, "file:line:column: gcode: ..."

  std::size_t warning_count() const;                 // warnings of every kind
  std::size_t count(const std::string& kind) const;  // warnings of `kind`; 0 when there were none
};

// The block reader: blocks in program order in, a Toolpath out.
class GcodeReader {
 public:
  // Validates the options first (validate(ReaderOptions)). `file_name` goes into messages.
  GcodeReader(const ReaderOptions& options, std::string file_name);
  ~GcodeReader();
  GcodeReader(GcodeReader&&) noexcept;
  GcodeReader& operator=(GcodeReader&&) noexcept;

  // One block, in program order. Throws InputError on bad input (see the file comment).
  void feed(const Block& block);
  // Room for `moves` moves in the toolpath (a hint, to spare copying it as it grows).
  void reserve(std::size_t moves);
  // True once M2 or M30 has ended the program.
  bool ended() const;
  const ReadStats& stats() const;  // what the blocks fed so far met
  // The toolpath read, layers indexed (Toolpath::index_layers). The reader is spent afterwards.
  Toolpath finish();

 private:
  class State;
  std::unique_ptr<State> state_;
};

}  // namespace beadtwin::gcode
