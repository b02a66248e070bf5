#include "gcode/block_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <span>
#include <stdexcept>

#include <fmt/format.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "gcode/annotations.hpp"
#include "gcode/arc.hpp"
#include "gcode/codes.hpp"
#include "gcode/toolpath_builder.hpp"

namespace beadtwin::gcode {
namespace {

std::string section_name(const std::string& file) {
  const std::string stem = std::filesystem::path(file).stem().string();
  return stem.empty() ? std::string("program") : stem;
}

}  // namespace

class GcodeReader::State {
 public:
  State(const ReaderOptions& o, std::string file)
      : opt_(o),
        file_(std::move(file)),
        codes_(o),
        builder_(section_name(file_), o.default_layer_height_mm,
                 [this](const std::string& kind, const std::string& message) { warn(kind, 0, message); }),
        inches_(o.inches),
        absolute_e_(o.absolute_e),
        volumetric_(o.volumetric_e),
        filament_area_mm2_(kPi * o.filament_diameter_mm * o.filament_diameter_mm / 4.0),
        roller_(o.roller_down_at_start),
        speed_(o.rpm_word.empty() ? '\0' : o.rpm_word.front()) {}

  bool ended() const { return ended_; }
  void reserve(std::size_t moves) { builder_.reserve(std::min(moves, opt_.max_moves)); }
  const ReadStats& stats() const { return stats_; }

  void feed(const Block& b) {
    if (finished_) throw InternalError("GcodeReader::feed after finish");
    if (ended_) return;
    ++stats_.blocks;
    line_ = b.line;
    if (b.block_delete && opt_.block_delete) {
      ++stats_.deleted_blocks;
      return;
    }
    for (const std::string& c : b.comments) annotate(c);
    check_numbers(b);
    SortedBlock& s = sort(b);
    run(s);
    for (const Word& w : s.params.unused())
      warn(fmt::format("unused word {}", w.letter), w.column,
           fmt::format("word {} is not used by any code in its block; ignored", w.letter));
  }

  Toolpath finish() {
    if (finished_) throw InternalError("GcodeReader::finish called twice");
    flush_pending();
    if (stats_.layer_markers > 0 && stats_.layer_markers != builder_.layers()) {
      line_ = 0;
      warn("layer markers", 0,
           fmt::format("the program's comments mark {} layer changes, but material is laid at {} heights",
                       stats_.layer_markers, builder_.layers()));
    }
    finished_ = true;
    stats_.moves = builder_.size();
    return builder_.finish();
  }

 private:
  double scale() const { return inches_ ? kMmPerInch : 1.0; }

  void warn(const std::string& kind, int column, const std::string& message) {
    if (stats_.warnings[kind]++ == 0 && stats_.messages.size() < opt_.max_messages)
      stats_.messages.push_back(format_input_error({file_, line_, column}, "gcode", message));
  }

  [[noreturn]] void fail(int column, const std::string& message) const {
    throw InputError({file_, line_, column}, "gcode", message);
  }

  // ---- comments ----

  void annotate(const std::string& comment) {
    const Annotation a = read_annotation(comment);
    if (a.layer_marker) {
      ++stats_.layer_markers;
      builder_.layer_marker();
    }
    if (a.height) builder_.set_height(*a.height * (a.height_in_program_units ? scale() : 1.0));
    if (a.width_mm) builder_.set_width(*a.width_mm);
    if (a.feature) {
      feature_ = *a.feature;
      pass_ = a.pass;
    }
    if (!a.unknown_type.empty())
      warn("feature type " + a.unknown_type, 0,
           fmt::format("feature type '{}' maps to no feature; its moves are 'unknown'", a.unknown_type));
    if (!a.malformed.empty())
      warn("annotation", 0, fmt::format("annotation '{}' has no usable number", a.malformed));
  }

  // ---- words ----

  void check_numbers(const Block& b) const {
    for (const Word& w : b.words) {
      if (!std::isfinite(w.value)) fail(w.column, fmt::format("word {} is not a finite number", w.letter));
      const bool length = std::string_view("XYZIJKR").find(w.letter) != std::string_view::npos;
      if (length && std::abs(w.value) * scale() > opt_.max_coordinate_mm)
        fail(w.column,
             fmt::format("{}{} is {:.4g} m away: farther than {:.4g} m, not a coordinate of this machine",
                         w.letter, w.value, std::abs(w.value) * scale() / 1000.0,
                         opt_.max_coordinate_mm / 1000.0));
      if ((w.letter == 'F' || w.letter == 'S' || w.letter == speed_) && w.value < 0.0)
        fail(w.column, fmt::format("{} must not be negative, got {}", w.letter, w.value));
    }
  }

  SortedBlock& sort(const Block& b) {
    SortedBlock& s = sorted_;
    s.clear();
    // A tool change, T with or without M6 on its line, is one warning: one extruder is modelled.
    const Word* tool = nullptr;
    const Word* m6 = nullptr;
    for (const Word& w : b.words) {
      if (w.letter == 'G') {
        const int g = code_tenths(w.value);
        if (g == 0 || g == 10 || g == 20 || g == 30)
          s.motion = w;
        else if (g == 40)
          s.dwell = w;
        else if (g == 920)
          s.set_position = w;
        else if (g == 280)
          s.home = w;
        else if (g == 170 || g == 180 || g == 190 || g == 200 || g == 210 || g == 900 || g == 910)
          s.modal_g.push_back(w);
        else if (codes_.ignored.matches(w))
          s.unhandled.push_back(w);
        else
          s.unknown.push_back(w);
      } else if (w.letter == 'M') {
        if (codes_.acts_on(w))
          s.m.push_back(w);
        else if (code_tenths(w.value) == 60)
          m6 = &w;
        else if (codes_.ignored.matches(w))
          s.unhandled.push_back(w);
        else
          s.unknown.push_back(w);
      } else if (w.letter == 'O' || w.letter == 'N') {
        // program and line numbers
      } else if (w.letter == 'T') {
        s.tool = w;
        if (w.value != 0.0) tool = &w;
      } else {
        s.params.add(w);
      }
    }
    // M104 T1 S200 sets another tool's heater: no tool change.
    const bool heater = has_m(s, codes_.nozzle_temp);
    if (tool && !heater)
      warn("tool change", tool->column,
           fmt::format("tool change T{} ignored: one extruder is modelled", tool->value));
    else if (m6 && !heater)
      warn("tool change", m6->column, "tool change (M6) ignored: one extruder is modelled");
    for (const Word& w : s.unknown) {
      const std::string code = fmt::format("{}{}", w.letter, w.value);
      warn("unknown code " + code, w.column,
           fmt::format("unknown code {}; ignored with its parameters", code));
      s.unhandled.push_back(w);
    }
    return s;
  }

  static bool is(const Word& w, char letter, int tenths) {
    return w.letter == letter && code_tenths(w.value) == tenths;
  }

  bool has_m(const SortedBlock& s, const CodeSet& set) const {
    return std::any_of(s.m.begin(), s.m.end(), [&](const Word& w) { return set.matches(w); });
  }

  // ---- one block, in the order a controller runs it ----

  void run(SortedBlock& s) {
    // An ignored or unknown code owns the block's parameters (M104 S200, M204 S800, M203 X200 ...).
    // So does a heater's target (M104 S215): read first.
    const bool heater = has_m(s, codes_.nozzle_temp);
    const bool housekeeping =
        (!s.unhandled.empty() || heater) && !(s.motion || s.dwell || s.set_position || s.home);
    if (heater) nozzle_temp(s);
    if (housekeeping) {
      s.params.take_all();
    } else {
      if (const auto f = s.params.take('F')) feed_mm_s_ = *f * scale() / 60.0;
      // A dwell's S is its time, M200's S a switch, a reverse code's speed word the reverse speed.
      const bool speed_word =
          speed_ != '\0' && !s.dwell && !has_m(s, codes_.reverse_on) && !has_m(s, codes_.fan_on) && !heater &&
          std::none_of(s.m.begin(), s.m.end(), [](const Word& w) { return is(w, 'M', 2000); });
      if (const auto rpm = speed_word ? s.params.take(speed_) : std::nullopt)
        set_rpm(*rpm, s.params.column(speed_));
    }
    modes(s);
    events_before(s);
    if (!housekeeping) act(s);
    events_after(s);
    if (std::any_of(s.m.begin(), s.m.end(),
                    [](const Word& w) { return is(w, 'M', 20) || is(w, 'M', 300); })) {
      ended_ = true;
      stats_.ended = true;
    }
  }

  // The block's one action: a dwell, a new position, homing, or motion in the modal G0-G3.
  void act(SortedBlock& s) {
    if (s.dwell) {
      dwell(s);
    } else if (s.set_position) {
      set_position(s);
    } else if (s.home) {
      home(s);
    } else {
      if (s.motion) motion_ = code_tenths(s.motion->value) / 10;
      if (has_motion_words(s.params)) motion(s);
    }
  }

  void set_rpm(double rpm, int column) {
    if (rpm > 0.0 && !(opt_.extruder && opt_.extruder->has_rpm()))
      warn("speed without extruder", column,
           fmt::format("{} (pump speed) without an extruder in the reader options: its flow is not known",
                       speed_));
    rpm_ = rpm;
  }

  void modes(SortedBlock& s) {
    for (const Word& w : s.modal_g) {
      const int g = code_tenths(w.value);
      if (g == 170 || g == 180 || g == 190)
        plane_ = g == 170 ? ArcPlane::kXY : (g == 180 ? ArcPlane::kZX : ArcPlane::kYZ);
      if (g == 200 || g == 210) inches_ = g == 200;
      if (g == 900 || g == 910) absolute_ = absolute_e_ = g == 900;
    }
    for (const Word& w : s.m) {
      if (is(w, 'M', 820)) absolute_e_ = true;
      if (is(w, 'M', 830)) absolute_e_ = false;
      if (is(w, 'M', 2000)) volumetric_mode(s.params);
    }
  }

  // The fan-on code's output S (0 to ReaderOptions::fan_full; none: full) for the part-cooling fan: P0 or P1,
  // or no P (another P is another fan, such as a chamber's, and changes nothing here).
  void fan(Params& p) {
    const std::optional<double> index = p.take('P');
    const std::optional<double> output = p.take('S');
    if (index && *index != 0.0 && *index != 1.0) return;
    fan_ = output ? static_cast<float>(std::clamp(*output / opt_.fan_full, 0.0, 1.0)) : 1.0f;
  }

  // The hot end's target (ReaderOptions::nozzle_temp): S, or M109's R (wait while heating or cooling), in
  // °C for the tool in use (no T, or T0); S0 turns the heater off and leaves the beads' temperature alone.
  void nozzle_temp(SortedBlock& s) {
    const std::optional<double> target = s.params.take('S');
    const std::optional<double> either_way = s.params.take('R');
    if (s.tool && s.tool->value != 0.0) return;
    const std::optional<double> c = target ? target : either_way;
    if (c && *c > 0.0) nozzle_c_ = static_cast<float>(*c);
  }

  // M200 D<diameter> (D0: off), S0/S1 (Marlin 2: off/on).
  void volumetric_mode(Params& p) {
    if (const auto d = p.take('D')) {
      volumetric_ = *d > 0.0;
      if (*d > 0.0) filament_area_mm2_ = kPi * (*d * scale()) * (*d * scale()) / 4.0;
    }
    if (const auto on = p.take('S')) volumetric_ = *on != 0.0;
  }

  void events_before(SortedBlock& s) {
    for (const Word& w : s.m) {
      if (codes_.heat_on.matches(w)) event(ExtruderEvent::kHeatOn);
      if (codes_.roller_down.matches(w)) roller_ = true;
      if (codes_.roller_up.matches(w)) roller_ = false;
      if (codes_.fan_on.matches(w)) fan(s.params);
      if (codes_.fan_off.matches(w)) fan_ = 0.0f;
      if (codes_.reverse_off.matches(w)) {
        flush_pending();
        reversing_ = false;
      }
      if (codes_.melt_on.matches(w) && !melt_) {
        flush_pending();
        reversing_ = false;
        melt_ = true;
        event(ExtruderEvent::kMeltOn);
      }
      if (codes_.prime.matches(w)) {
        flush_pending();
        prime_pending_ = true;
      }
    }
  }

  void events_after(SortedBlock& s) {
    for (const Word& w : s.m) {
      if (codes_.melt_off.matches(w) && melt_) {
        flush_pending();
        melt_ = false;
        event(ExtruderEvent::kMeltOff);
      }
      if (codes_.reverse_on.matches(w)) {
        flush_pending();
        reversing_ = true;
        reverse_pending_ = true;
        if (speed_ != '\0') s.params.take(speed_);  // the reverse speed: the pump draws back, nothing is laid
      }
      if (codes_.heat_off.matches(w)) event(ExtruderEvent::kHeatOff);
    }
  }

  // A prime or reverse code not followed by its dwell: the event happens while the head moves on.
  void flush_pending() {
    if (prime_pending_) {
      prime_pending_ = false;
      event(ExtruderEvent::kPrime);
    }
    if (reverse_pending_) {
      reverse_pending_ = false;
      event(ExtruderEvent::kReverse);
    }
  }

  bool pump_running() const {
    if (reversing_) return false;
    return codes_.melt_on.empty() ? rpm_ > 0.0 : melt_;
  }

  // Flow of the running pump, mm³/s: its speed word's, else a filament drive's constant feed; 0 when not
  // known.
  double pump_flow_mm3_s() const {
    if (!pump_running() || !opt_.extruder) return 0.0;
    if (rpm_ > 0.0 && opt_.extruder->has_rpm()) return flow_for_rpm(*opt_.extruder, rpm_);
    if (opt_.extruder->has_constant_feed())
      return flow_for_filament_feed(*opt_.extruder, opt_.extruder->constant_feed_mm_s);
    return 0.0;
  }

  void dwell(SortedBlock& s) {
    double t = 0.0;
    if (const auto p = s.params.take('P')) t = opt_.dwell_p_seconds ? *p : *p / 1000.0;
    if (const auto sec = s.params.take('S')) t = *sec;
    if (const auto x = s.params.take('X')) t = *x;
    if (t < 0.0) fail(s.dwell->column, fmt::format("a dwell cannot last a negative time, got {} s", t));
    Move m = here();
    m.kind = MoveKind::kDwell;
    m.duration_s = t;
    m.volume_mm3 = pump_flow_mm3_s() * t;
    if (reverse_pending_) {
      reverse_pending_ = false;
      m.event = ExtruderEvent::kReverse;
      m.feature = Feature::kReverse;
    } else if (prime_pending_ || m.deposits()) {
      prime_pending_ = false;
      m.event = ExtruderEvent::kPrime;
      m.feature = Feature::kPrime;
    }
    flush_pending();
    emit(std::move(m));
  }

  void set_position(SortedBlock& s) {
    for (int a = 0; a < 3; ++a)
      if (const auto v = s.params.take("XYZ"[a])) origin_[a] = pos_[a] - *v * scale();
    if (const auto e = s.params.take('E')) e_ = *e;
    bool turned = false;
    for (int r = 0; r < 3; ++r)
      if (const auto v = s.params.take("ABC"[r])) {
        rotary_[r] = *v;
        turned = true;
      }
    if (turned) builder_.set_rotary(rotary_);
  }

  void home(SortedBlock& s) {
    bool any = false;
    for (int a = 0; a < 3; ++a)
      if (s.params.take("XYZ"[a])) {
        any = true;
        pos_[a] = origin_[a] = 0.0;
      }
    if (!any) pos_ = origin_ = Eigen::Vector3d::Zero();
    for (const char r : {'A', 'B', 'C'}) s.params.take(r);
  }

  static bool has_motion_words(const Params& p) {
    for (const char c : {'X', 'Y', 'Z', 'E', 'A', 'B', 'C', 'I', 'J', 'K', 'R'})
      if (p.has(c)) return true;
    return false;
  }

  // ---- motion ----

  void motion(SortedBlock& s) {
    Params& p = s.params;
    if (motion_ < 0) {
      warn("no motion mode", p.column('X'), "axis words before any G0/G1/G2/G3: taken as G1");
      motion_ = 1;
    }
    Eigen::Vector3d target = pos_;
    for (int a = 0; a < 3; ++a)
      if (const auto v = p.take("XYZ"[a])) target[a] = (absolute_ ? origin_[a] : target[a]) + *v * scale();
    // Rotary axes (degrees, not scaled by G20): kept with the moves, not yet part of the kinematics.
    bool turned = false;
    for (int r = 0; r < 3; ++r)
      if (const auto v = p.take("ABC"[r])) {
        rotary_[r] = absolute_ ? *v : rotary_[r] + *v;
        turned = true;
      }
    if (turned) builder_.set_rotary(rotary_);
    for (int a = 0; a < 3; ++a)
      if (std::abs(target[a]) > opt_.max_coordinate_mm)
        fail(p.column("XYZ"[a]), fmt::format("the move reaches {} = {:.4g} m: farther than {:.4g} m",
                                             "XYZ"[a], target[a] / 1000.0, opt_.max_coordinate_mm / 1000.0));
    std::optional<double> fed_mm3;  // E fed by the block, as volume (negative: drawn back)
    if (const auto e = p.take('E')) {
      const double next = absolute_e_ ? *e : e_ + *e;
      const double de = next - e_;
      e_ = next;
      fed_mm3 = volumetric_ ? de * scale() * scale() * scale() : de * scale() * filament_area_mm2_;
    }
    flush_pending();
    if (motion_ == 2 || motion_ == 3) {
      arc(s, target, fed_mm3);
      return;
    }
    if (target == pos_) {
      if (fed_mm3 && *fed_mm3 != 0.0) in_place(*fed_mm3);
      return;
    }
    const std::array<Eigen::Vector3d, 2> points = {pos_, target};
    lay(points, fed_mm3);
  }

  // E fed or drawn back with the head standing: a prime (unretract) or a reverse (retraction).
  void in_place(double fed_mm3) {
    Move m = here();
    m.kind = MoveKind::kDwell;
    const double e_mm = volumetric_ ? fed_mm3 : fed_mm3 / filament_area_mm2_;
    m.duration_s = std::abs(e_mm) / feed_or_default(0);
    if (fed_mm3 < 0.0) {
      owed_mm3_ -= fed_mm3;
      m.event = ExtruderEvent::kReverse;
      m.feature = Feature::kReverse;
    } else {
      m.volume_mm3 = pay_debt(fed_mm3);
      m.event = ExtruderEvent::kPrime;
      m.feature = Feature::kPrime;
    }
    emit(std::move(m));
  }

  // What of `fed_mm3` is laid once the nozzle is refilled after retractions.
  double pay_debt(double fed_mm3) {
    if (!opt_.refill_after_retract) return fed_mm3;
    const double refill = std::min(fed_mm3, owed_mm3_);
    owed_mm3_ -= refill;
    return fed_mm3 - refill;
  }

  double feed_or_default(int column) {
    if (feed_mm_s_ > 0.0) return feed_mm_s_;
    warn("no feed", column,
         fmt::format("a move before any F: taken at the default feed of {} mm/s", opt_.default_feed_mm_s));
    return opt_.default_feed_mm_s;
  }

  void arc(SortedBlock& s, const Eigen::Vector3d& target, std::optional<double> fed_mm3) {
    Params& p = s.params;
    ++stats_.arcs;
    const bool clockwise = motion_ == 2;
    const PlaneAxes axes = plane_axes(plane_);
    const char offset_letter[3] = {'I', 'J', 'K'};
    Eigen::Vector3d centre = pos_;
    bool has_offset = false;
    for (int a = 0; a < 3; ++a)
      if (const auto v = p.take(offset_letter[a])) {
        has_offset = true;
        if (a != axes.n) centre[a] += *v * scale();
      }
    const auto r = p.take('R');
    int turns = 1;
    if (const auto t = p.take('P')) {
      if (*t < 1.0 || *t != std::floor(*t) || *t > 1000.0)
        fail(p.column('P'),
             fmt::format("P (turns of an arc) must be a whole number from 1 to 1000, got {}", *t));
      turns = static_cast<int>(*t);
    }
    try {
      if (r && !has_offset) {
        centre = arc_centre_from_radius(pos_, target, plane_, clockwise, *r * scale());
      } else if (!has_offset) {
        fail(s.motion ? s.motion->column : 0, "an arc needs its centre: I/J/K offsets or a radius R");
      }
      const std::size_t room = opt_.max_moves > builder_.size() ? opt_.max_moves - builder_.size() : 0;
      std::vector<Eigen::Vector3d> points =
          linearise_arc(pos_, target, centre, plane_, clockwise, turns, opt_.chord_tolerance_mm, room);
      points.insert(points.begin(), pos_);
      lay(points, fed_mm3);
    } catch (const std::invalid_argument& e) {
      fail(p.column('R'), e.what());
    } catch (const std::length_error& e) {
      fail(s.motion ? s.motion->column : 0, e.what());
    }
  }

  // Moves along `points` (the first is the head's position): print or travel, the material `fed_mm3` (E)
  // or the pump's spread over them by length.
  void lay(std::span<const Eigen::Vector3d> points, std::optional<double> fed_mm3) {
    double length = 0.0;
    for (std::size_t k = 1; k < points.size(); ++k) length += (points[k] - points[k - 1]).norm();
    const bool rapid = motion_ == 0;
    const double feed = rapid && opt_.rapid_feed_mm_s > 0.0 ? opt_.rapid_feed_mm_s : feed_or_default(0);
    double volume = 0.0;  // laid over the whole path
    bool print = false;
    if (fed_mm3) {
      if (*fed_mm3 < 0.0) owed_mm3_ -= *fed_mm3;
      if (*fed_mm3 > 0.0 && rapid)
        warn("material on G0", 0, "E fed on a rapid move (G0): not booked as material");
      else if (*fed_mm3 > 0.0) {
        volume = pay_debt(*fed_mm3);
        print = true;
      }
    } else if (!rapid && pump_running()) {
      print = true;
      const double flow = pump_flow_mm3_s();
      if (flow > 0.0) {
        volume = flow * length / feed;
      } else if (opt_.default_bead_width_mm > 0.0 && opt_.default_layer_height_mm > 0.0) {
        volume = bead_area_mm2(opt_.default_bead_width_mm, opt_.default_layer_height_mm) * length;
      } else {
        warn("unknown flow", 0,
             "melt on, but neither the pump's speed and an extruder, a constant filament feed nor a default "
             "bead give the flow: the print moves carry no material");
      }
    }
    for (std::size_t k = 1; k < points.size(); ++k) {
      Move m = here();
      m.start = points[k - 1];
      m.end = points[k];
      m.feed_mm_s = feed;
      if (print) {
        m.kind = MoveKind::kPrint;
        m.feature = feature_;
        m.pass = feature_ == Feature::kBoundary ? pass_ : -1;
        m.volume_mm3 = length > 0.0 ? volume * m.length_mm() / length : 0.0;
      } else {
        m.kind = MoveKind::kTravel;
      }
      emit(std::move(m));
    }
    pos_ = points.back();
  }

  // ---- moves, layers, beads ----

  // A move at the head's position, from the current line, with the roller's state.
  Move here() const {
    Move m;
    m.start = m.end = pos_;
    m.feature = Feature::kTravel;
    m.roller_down = roller_;
    m.fan = fan_;
    m.nozzle_c = nozzle_c_;
    m.source_line = line_;
    return m;
  }

  void event(ExtruderEvent e) {
    Move m = here();
    m.kind = MoveKind::kDwell;
    m.event = e;
    if (e == ExtruderEvent::kPrime) m.feature = Feature::kPrime;
    if (e == ExtruderEvent::kReverse) m.feature = Feature::kReverse;
    emit(std::move(m));
  }

  void emit(Move m) {
    if (builder_.size() >= opt_.max_moves)
      fail(0, fmt::format("the program makes more than {} moves, the most beadtwin reads in one program "
                          "(their toolpath alone would take {:.2g} GB); split it into shorter programs",
                          opt_.max_moves, static_cast<double>(opt_.max_moves * sizeof(Move)) / 1e9));
    builder_.add(std::move(m));
  }

  ReaderOptions opt_;
  std::string file_;
  CodeSets codes_;
  ReadStats stats_;
  SortedBlock sorted_;  // the block being run
  GcodeToolpathBuilder builder_;
  Eigen::Vector3d rotary_ = Eigen::Vector3d::Zero();  // A, B, C, degrees
  int line_ = 0;
  bool ended_ = false;
  bool finished_ = false;

  // Modes.
  bool inches_;
  bool absolute_ = true;
  bool absolute_e_;
  bool volumetric_;
  double filament_area_mm2_;
  ArcPlane plane_ = ArcPlane::kXY;
  int motion_ = -1;  // modal G0..G3; -1 before any

  // Machine state.
  Eigen::Vector3d pos_ = Eigen::Vector3d::Zero();     // machine position, mm
  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();  // where the program's 0 is (G92), mm
  double e_ = 0.0;                                    // E as the program counts it
  double feed_mm_s_ = 0.0;                            // 0 before any F
  double rpm_ = 0.0;
  double owed_mm3_ = 0.0;  // material drawn back by retractions, refilled before any is laid
  bool melt_ = false;
  bool reversing_ = false;
  bool prime_pending_ = false;
  bool reverse_pending_ = false;
  bool roller_;
  float fan_ = 0.0f;                                          // the part-cooling fan's output, 0..1
  float nozzle_c_ = std::numeric_limits<float>::quiet_NaN();  // the hot end's target, °C; NaN: none yet
  const char speed_;  // the speed word's letter (ReaderOptions::rpm_word); '\0': none

  // What comments said.
  Feature feature_ = Feature::kUnknown;
  int pass_ = -1;
};

GcodeReader::GcodeReader(const ReaderOptions& options, std::string file_name) {
  validate(options);
  state_ = std::make_unique<State>(options, std::move(file_name));
}
GcodeReader::~GcodeReader() = default;
GcodeReader::GcodeReader(GcodeReader&&) noexcept = default;
GcodeReader& GcodeReader::operator=(GcodeReader&&) noexcept = default;

void GcodeReader::feed(const Block& block) {
  state_->feed(block);
}
void GcodeReader::reserve(std::size_t moves) {
  state_->reserve(moves);
}
bool GcodeReader::ended() const {
  return state_->ended();
}
const ReadStats& GcodeReader::stats() const {
  return state_->stats();
}
Toolpath GcodeReader::finish() {
  return state_->finish();
}

std::size_t ReadStats::warning_count() const {
  std::size_t n = 0;
  for (const auto& [kind, count] : warnings) n += count;
  return n;
}

std::size_t ReadStats::count(const std::string& kind) const {
  const auto it = warnings.find(kind);
  return it == warnings.end() ? 0 : it->second;
}

}  // namespace beadtwin::gcode
