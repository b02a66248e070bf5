// Reading G-code programs into the Toolpath IR (core/toolpath.hpp): a program from any slicer, or one of
// our own (gcode/writer.hpp), becomes the moves, layers and extruder events the simulation runs on.
//
// The reader consumes Blocks (gcode/block.hpp) one at a time, from the plain lexer
// (gcode/lexer.hpp) or from the macro interpreter, and keeps only the Toolpath it builds: memory
// grows with the moves, not with the program's text.
//
// What the blocks mean:
//   motion     G0 is travel, at ReaderOptions::rapid_feed_mm_s where the controller runs G0 at its rapid
//              traverse (CNC controllers), else at the programmed F (Marlin). G1, G2 and G3 print when
//              material flows: the E word grows (filament machines),
//              or, without an E word, the melt is on and the pump turns (pump machines; the S word is its
//              speed in rev/min, turned into flow by ReaderOptions::extruder; a filament drive with a
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
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/flow.hpp"
#include "core/toolpath.hpp"
#include "gcode/block.hpp"
#include "gcode/writer.hpp"

namespace beadtwin::gcode {

// Firmware and controller housekeeping that changes nothing the Toolpath records (temperatures, fans,
// motors, acceleration limits, progress, bed levelling, work offset G54...): read silently.
std::vector<std::string> default_ignored_codes();

// What a program's codes mean on the machine that runs it, and the modes it starts in. A code is a letter
// and a number, "M23" or "M862.3".
struct ReaderOptions {
  // Extruder feed on (add "M3" for spindle-style pumps). Empty: the pump runs whenever S > 0.
  std::vector<std::string> melt_on = {"M23"};
  std::vector<std::string> melt_off = {"M24"};  // extruder feed off (add "M5")
  std::vector<std::string> heat_on = {"M27"};   // extruder heaters on
  std::vector<std::string> heat_off = {"M28"};  // extruder heaters off
  std::vector<std::string> roller_down;         // compression roller engaged
  std::vector<std::string> roller_up;           // compression roller lifted
  // The roller is engaged from the start (until a roller-up code): a roller machine whose programs carry no
  // roller codes rolls every bead.
  bool roller_down_at_start = false;
  std::vector<std::string> prime;        // a prime starts (its time: the G4 after it)
  std::vector<std::string> reverse_on;   // the pump turns backwards (its S is the reverse speed)
  std::vector<std::string> reverse_off;  // it stops turning backwards
  std::vector<std::string> ignored = default_ignored_codes();

  bool inches = false;                 // units before any G20/G21
  bool absolute_e = true;              // E mode before any M82/M83 (or G90/G91)
  bool dwell_p_seconds = false;        // G4 P in seconds (Fanuc-style programs, ours) instead of milliseconds
  bool block_delete = true;            // the block delete switch: blocks starting with `/` are skipped
  long max_macro_steps = 10'000'000;   // macro programs: statements run before an endless loop is an error
  double filament_diameter_mm = 1.75;  // E times π d²/4 is the volume fed, unless E is volumetric
  // A program that states its filament diameter (PrusaSlicer and Slic3r write `; filament_diameter = d` in
  // the settings at its end) is read with that diameter: its E words were computed for it.
  bool filament_diameter_from_program = true;
  bool volumetric_e = false;  // E is volume (mm³, in³ under G20) from the start

  // The pump or screw (kGearPump, kScrew): turns the S word (rev/min) into flow; or a filament drive, whose
  // constant feed (if any) is the flow between melt on and melt off where moves carry no E word. Without
  // one, a pump program's print moves lay the default bead, or nothing when there is none.
  std::optional<Extruder> extruder;
  bool refill_after_retract = true;    // E fed after a retraction refills the nozzle before material is laid
  double default_bead_width_mm = 0.0;  // the bead a print move of unknown flow lays (0: none)
  double default_layer_height_mm = 0.0;  // its height, also when a layer's own cannot be found (0: none)
  double default_feed_mm_s = 25.0;       // feed of moves before the first F
  double rapid_feed_mm_s = 0.0;          // feed of G0 moves; 0: the programmed F (as Marlin does)

  double chord_tolerance_mm = 0.01;    // arcs become chords within this distance of the circle
  double max_coordinate_mm = 1e5;      // 100 m: anything farther is not a coordinate of this machine
  std::size_t max_moves = 20'000'000;  // a program making more moves is refused
  std::size_t max_messages = 20;       // warning messages kept (all are counted)
};

// Throws InputError (key "reader", the message naming each option "reader.<option>" at fault) for every
// problem found: a code that is not a letter and a number, a filament diameter, chord tolerance or feed that
// is not positive, negative defaults, an extruder that does not validate.
void validate(const ReaderOptions& options);

// The options that read back a program written by write_gcode with `dialect` and, if any, `extruder`:
// its melt, roller, prime and reverse codes, G4 P in milliseconds, its units, the extruder's filament or
// pump.
ReaderOptions reader_options_for(const GcodeDialect& dialect, const Extruder* extruder);

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

  std::size_t warning_count() const;
  std::size_t count(const std::string& kind) const;
};

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
  const ReadStats& stats() const;
  // The toolpath read, layers indexed (Toolpath::index_layers). The reader is spent afterwards.
  Toolpath finish();

 private:
  class State;
  std::unique_ptr<State> state_;
};

// The value of a setting a program states in the block PrusaSlicer and Slic3r write at its end ("; key =
// value"), as written, found in the last 256 kB of a seekable stream without reading the rest; the stream
// is left where it was. None when the stream cannot seek or states no such setting.
std::optional<std::string> stated_setting(std::istream& in, std::string_view key);

// Reads the program in `in` line by line (lexer, then reader) until its end or M2/M30. Throws InputError
// for a file that is not text (NUL bytes or a line over 1 MB), a line with macro syntax (the program needs
// the macro interpreter), and everything GcodeReader::feed refuses. `stats`, if given, receives the reading
// statistics.
Toolpath read_gcode(std::istream& in, const std::string& file_name, const ReaderOptions& options = {},
                    ReadStats* stats = nullptr);

}  // namespace beadtwin::gcode
