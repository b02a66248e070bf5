// Print-program dialects: Marlin/RepRap E words, relative (M83) and absolute (M82), and
// machines without melt codes.
#include <algorithm>
#include <regex>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/flow.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/writer.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::slicer {
namespace {

Toolpath small_part() {
  SectionParams s;
  s.name = "all";
  s.z_max_mm = 1;
  s.layer_height_mm = 0.2;
  s.bead_width_mm = 0.45;
  s.print_speed_mm_s = 40;
  s.travel_speed_mm_s = 150;
  s.boundary.passes = 2;
  s.fill.enabled = true;
  return plan_toolpath(make_box({30, 20, 1}), {s}, {});
}

// Sum of E over a relative program, or the last E of an absolute one.
double filament_total(const std::string& program, bool absolute) {
  std::istringstream in(program);
  const std::regex e_word(R"( E(-?[0-9.]+))");
  double total = 0;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (line.rfind("G1", 0) != 0 || !std::regex_search(line, m, e_word)) continue;
    total = absolute ? std::stod(m[1]) : total + std::stod(m[1]);
  }
  return total;
}

TEST(GcodeDialect, RelativeAndAbsoluteEWordsFeedTheSameFilament) {
  const Toolpath tp = small_part();
  Extruder filament;
  filament.kind = ExtruderKind::kFilament;
  filament.filament_diameter_mm = 1.75;
  gcode::GcodeOptions o;
  o.extruder = &filament;
  gcode::GcodeDialect d;
  d.melt_on.clear();
  d.melt_off.clear();
  const std::string relative = gcode::write_gcode(tp, d, {}, o);
  d.absolute_e = true;
  const std::string absolute = gcode::write_gcode(tp, d, {}, o);
  EXPECT_NE(relative.find("M83"), std::string::npos);
  EXPECT_NE(absolute.find("M82"), std::string::npos);
  EXPECT_NE(absolute.find("G92 E0"), std::string::npos);
  // Machines without melt codes get comments, never M23 (which Marlin reads as "select SD file").
  EXPECT_EQ(relative.find("M23"), std::string::npos);
  EXPECT_NE(relative.find("(melt on)"), std::string::npos);
  // Both feed the filament the bead needs: V / (π d²/4), to the program's last decimal.
  const double expected = tp.commanded_volume_mm3() / filament_area_mm2(filament);
  EXPECT_NEAR(filament_total(relative, false), expected, 1e-3);
  EXPECT_NEAR(filament_total(absolute, true), expected, 1e-3);
}

// Heating codes: M27 at the program's start, M28 at its end (seed 002's), or a machine's own; read back as
// heater events with the machine's codes.
TEST(GcodeDialect, HeatersOnAtTheStartOffAtTheEnd) {
  const Toolpath tp = small_part();
  for (const auto& [on_code, off_code] : {std::pair{"M27", "M28"}, std::pair{"M127", "M128"}}) {
    gcode::GcodeDialect d;
    d.heat_on = on_code;
    d.heat_off = off_code;
    const std::string program = gcode::write_gcode(tp, d, {});
    const std::size_t on = program.find(fmt::format("\n{} (heaters on)\n", on_code));
    const std::size_t off = program.find(fmt::format("\n{} (heaters off)\n", off_code));
    ASSERT_NE(on, std::string::npos) << on_code;
    ASSERT_NE(off, std::string::npos) << off_code;
    EXPECT_LT(on, program.find("(LAYER 0"));
    EXPECT_GT(off, program.rfind("(LAYER "));
    EXPECT_LT(off, program.find("\nM30"));
    std::istringstream in(program);
    const Toolpath read = gcode::read_gcode(in, "heat.nc", gcode::reader_options_for(d, nullptr));
    int heat_on = 0, heat_off = 0;
    for (const Move& m : read.moves) {
      heat_on += m.event == ExtruderEvent::kHeatOn;
      heat_off += m.event == ExtruderEvent::kHeatOff;
    }
    EXPECT_EQ(heat_on, 1) << on_code;
    EXPECT_EQ(heat_off, 1) << off_code;
    // Written again, the events are the codes, once each.
    const std::string again = gcode::write_gcode(read, d, {});
    EXPECT_EQ(again.find(on_code), again.rfind(on_code));
    EXPECT_NE(again.find(on_code), std::string::npos);
  }
}

// A CNC controller (Fanuc, Siemens; ISO 6983-1) runs G0 at its rapid traverse whatever F says; Marlin runs it
// at F. A program's travel is read accordingly, and a writer for such a controller writes travel slower than
// the rapid traverse as G1, so that the machine keeps its feed.
TEST(GcodeDialect, AControllersRapidTraverseTimesItsG0AndSlowerTravelIsWrittenAsG1) {
  const std::string program =
      "G21 G90\nM24\nG1 X0 Y0 Z1 F60\n"  // 1 mm/s: the modal feed
      "G0 X300\n";                       // rapid: 300 mm
  gcode::GcodeDialect cnc;
  cnc.rapid_feed_mm_s = 500;
  const auto travel_feed = [&](const gcode::GcodeDialect& d) {
    std::istringstream in(program);
    const Toolpath tp = gcode::read_gcode(in, "rapid.nc", gcode::reader_options_for(d, nullptr));
    return tp.moves.back().feed_mm_s;
  };
  EXPECT_DOUBLE_EQ(travel_feed(cnc), 500.0);
  EXPECT_DOUBLE_EQ(travel_feed(gcode::GcodeDialect{}), 1.0);  // at F, as Marlin runs it

  // Travel at the rapid traverse is G0; slower travel is G1 at its feed, and reads back at that feed.
  Toolpath tp = small_part();  // travel at 150 mm/s
  const std::size_t travels = static_cast<std::size_t>(std::count_if(
      tp.moves.begin(), tp.moves.end(), [](const Move& m) { return m.kind == MoveKind::kTravel; }));
  ASSERT_GT(travels, 2u);
  const auto count = [](const std::string& text, const std::string& code) {
    std::size_t n = 0;
    for (std::size_t at = text.find("\n" + code + " "); at != std::string::npos;
         at = text.find("\n" + code + " ", at + 1))
      ++n;
    return n;
  };
  cnc.rapid_feed_mm_s = 150;
  EXPECT_EQ(count(gcode::write_gcode(tp, cnc, {}), "G0"), travels);
  cnc.rapid_feed_mm_s = 500;
  const std::string slower = gcode::write_gcode(tp, cnc, {});
  EXPECT_EQ(count(slower, "G0"), 0u);
  std::istringstream in(slower);
  const Toolpath read = gcode::read_gcode(in, "slower.nc", gcode::reader_options_for(cnc, nullptr));
  for (const Move& m : read.moves) {
    if (m.kind == MoveKind::kTravel && m.length_mm() > 0) {
      EXPECT_NEAR(m.feed_mm_s, 150.0, 1e-6);
    }
  }
}

}  // namespace
}  // namespace beadtwin::slicer
