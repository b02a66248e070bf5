// Fanuc macro print programs (seed 002, section 2.7): repeated layers written once in a WHILE loop must
// command what the plain program commands.
#include "gcode/macro_loops.hpp"

#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/toolpath.hpp"
#include "gcode/macro.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/writer.hpp"

namespace beadtwin::gcode {
namespace {

using Eigen::Vector3d;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// The motion blocks of a program with its one-level WHILE loops unrolled by hand (the loop counter #100,
// the Z variable #101 = z0 + #100 * step), comments dropped.
std::vector<std::string> unrolled(const std::string& program) {
  const std::vector<std::string> lines = lines_of(program);
  std::vector<std::string> out;
  const std::regex z_of(R"(#101=([-0-9.]+)\+#100\*([-0-9.]+))"), count_of(R"(WHILE \[#100 LT (\d+)\] DO 1)");
  auto strip = [](std::string l) { return l.substr(0, l.find(" (")); };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (!std::regex_search(lines[i], m, count_of)) {
      if (lines[i].empty() || lines[i][0] == '(' || lines[i][0] == '#') continue;
      out.push_back(strip(lines[i]));
      continue;
    }
    const int count = std::stoi(m[1]);
    std::size_t end = i + 1;
    while (lines[end] != "END 1") ++end;
    std::smatch zm;
    EXPECT_TRUE(std::regex_search(lines[i + 1], zm, z_of)) << lines[i + 1];
    const double z0 = std::stod(zm[1]), step = std::stod(zm[2]);
    for (int k = 0; k < count; ++k)
      for (std::size_t j = i + 2; j < end; ++j) {
        if (lines[j][0] == '(' || lines[j][0] == '#') continue;
        std::string l = strip(lines[j]);
        const std::size_t at = l.find("Z#101");
        if (at != std::string::npos) {
          std::string z = fmt::format("{:.3f}", z0 + k * step);
          while (z.back() == '0') z.pop_back();
          if (z.back() == '.') z.pop_back();
          l.replace(at, 5, "Z" + z);
        }
        out.push_back(l);
      }
    i = end;
  }
  return out;
}

// An AM Outline ring as the planner lays one: `layers` 5 mm layers of a 20 mm bead around a 400 × 300 mm
// rectangle, each layer a travel up to its Z (none before the first), melt on, the sides at 60 mm/s with
// the roller down, melt off; timed by the motion model. Every layer is the same path one layer higher,
// unless `seam_step_mm` moves each layer's start (and end) that far along the first side.
Toolpath ring(int layers, double seam_step_mm = 0.0) {
  constexpr double kHeight = 5.0, kWidth = 20.0, kX = 400.0, kY = 300.0;
  Toolpath tp;
  tp.sections = {"ring"};
  for (int k = 0; k < layers; ++k) {
    const double z = kHeight * (k + 1), seam = seam_step_mm * k;
    ToolpathLayer layer;
    layer.z_mm = z;
    layer.height_mm = kHeight;
    layer.section = 0;
    tp.layers.push_back(layer);
    Move base;
    base.section = 0;
    base.layer = k;
    base.bead_width_mm = kWidth;
    base.layer_height_mm = kHeight;
    const Vector3d start(seam, 0, z);
    if (k > 0) {
      Move travel = base;
      travel.kind = MoveKind::kTravel;
      travel.feature = Feature::kTravel;
      travel.start = tp.moves.back().end;
      travel.end = start;
      travel.feed_mm_s = 300;
      tp.moves.push_back(travel);
    }
    Move on = base;
    on.kind = MoveKind::kDwell;
    on.event = ExtruderEvent::kMeltOn;
    on.start = on.end = start;
    tp.moves.push_back(on);
    Vector3d at = start;
    for (const Vector3d& corner :
         {Vector3d(kX, 0, z), Vector3d(kX, kY, z), Vector3d(0, kY, z), Vector3d(0, 0, z), start}) {
      if ((corner - at).norm() == 0.0) continue;
      Move side = base;
      side.kind = MoveKind::kPrint;
      side.feature = Feature::kBoundary;
      side.pass = 0;
      side.roller_down = true;
      side.start = at;
      side.end = corner;
      side.feed_mm_s = 60;
      side.volume_mm3 = bead_area_mm2(kWidth, kHeight) * side.length_mm();
      tp.moves.push_back(side);
      at = corner;
    }
    Move off = on;
    off.event = ExtruderEvent::kMeltOff;
    off.start = off.end = at;
    tp.moves.push_back(off);
  }
  time_toolpath(tp, MotionLimits{});
  return tp;
}

TEST(MacroLoops, RepeatedLayersBecomeOneWhileLoopCommandingTheSame) {
  const Toolpath tp = ring(8);
  GcodeDialect plain_d;
  const std::string plain = write_gcode(tp, plain_d, {});
  GcodeDialect loop_d;
  loop_d.macro_loops = true;
  const std::string looped = write_gcode(tp, loop_d, {});
  EXPECT_NE(looped.find("WHILE [#100 LT 7] DO 1"), std::string::npos) << looped;
  EXPECT_LT(lines_of(looped).size(), lines_of(plain).size() / 2);
  EXPECT_EQ(unrolled(looped), unrolled(plain));
  // Layers that differ (a seam moving along the path) stay as they are.
  const Toolpath moving = ring(8, 37);
  EXPECT_EQ(write_gcode(moving, loop_d, {}).find("WHILE"), std::string::npos);
}

// The looped program run by the macro interpreter commands the plain program's blocks, word for word.
TEST(MacroLoops, TheInterpreterRunsTheLoopIntoThePlainProgram) {
  const Toolpath tp = ring(10);
  GcodeDialect d;
  const std::string plain = write_gcode(tp, d, {});
  d.macro_loops = true;
  const std::string looped = write_gcode(tp, d, {});
  ASSERT_NE(looped.find("WHILE"), std::string::npos);
  auto blocks = [](const std::string& program) {
    std::vector<std::vector<std::pair<char, double>>> out;
    MacroProgram(program).run([&](const Block& b) {
      if (b.words.empty()) return;
      std::vector<std::pair<char, double>> words;
      for (const Word& w : b.words) words.emplace_back(w.letter, w.value);
      out.push_back(std::move(words));
    });
    return out;
  };
  const auto expected = blocks(plain), got = blocks(looped);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].size(), expected[i].size()) << "block " << i;
    for (std::size_t k = 0; k < got[i].size(); ++k) {
      EXPECT_EQ(got[i][k].first, expected[i][k].first) << "block " << i;
      EXPECT_NEAR(got[i][k].second, expected[i][k].second, 1e-9) << "block " << i;
    }
  }
}

// read_gcode hands a macro program to the interpreter: the looped program reads back as the plain one.
TEST(MacroLoops, ReadGcodeRunsMacroProgramsThroughTheInterpreter) {
  const Toolpath tp = ring(6);
  GcodeDialect d;
  const ReaderOptions ro = reader_options_for(d, nullptr);
  std::istringstream plain_in(write_gcode(tp, d, {}));
  d.macro_loops = true;
  std::istringstream looped_in(write_gcode(tp, d, {}));
  const Toolpath plain = read_gcode(plain_in, "plain.nc", ro),
                 looped = read_gcode(looped_in, "looped.nc", ro);
  ASSERT_EQ(looped.moves.size(), plain.moves.size());
  ASSERT_EQ(looped.layers.size(), 6u);
  for (std::size_t i = 0; i < plain.moves.size(); ++i) {
    EXPECT_NEAR((looped.moves[i].end - plain.moves[i].end).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR(looped.moves[i].volume_mm3, plain.moves[i].volume_mm3, 1e-9) << i;
    EXPECT_EQ(looped.moves[i].source_line > 0, true);
  }
  // An endless loop is an error naming its line, not a hang.
  std::istringstream endless("#1=0\nWHILE [#1 LT 1] DO 1\nG1 X1\nEND 1\nM30\n");
  ReaderOptions short_run = ro;
  short_run.max_macro_steps = 1000;
  EXPECT_THROW((void)read_gcode(endless, "endless.nc", short_run), InputError);
}

}  // namespace
}  // namespace beadtwin::gcode
