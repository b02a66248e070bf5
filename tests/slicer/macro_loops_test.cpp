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

#include "core/error.hpp"
#include "gcode/macro.hpp"
#include "gcode/program_reader.hpp"
#include "gcode/writer.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"

namespace beadtwin::slicer {
namespace {

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

// An AM Outline ring of `layers` 5 mm layers: every layer the same path.
SectionParams ring(int layers) {
  SectionParams s;
  s.name = "ring";
  s.z_max_mm = 5.0 * layers;
  s.layer_height_mm = 5;
  s.bead_width_mm = 20;
  s.print_speed_mm_s = 60;
  s.travel_speed_mm_s = 300;
  s.outline_path = {{0, 0}, {400, 0}, {400, 300}, {0, 300}};
  return s;
}

TEST(MacroLoops, RepeatedLayersBecomeOneWhileLoopCommandingTheSame) {
  SectionParams s = ring(8);
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {s}, {});
  gcode::GcodeDialect plain_d;
  const std::string plain = gcode::write_gcode(tp, plain_d, {});
  gcode::GcodeDialect loop_d;
  loop_d.macro_loops = true;
  const std::string looped = gcode::write_gcode(tp, loop_d, {});
  EXPECT_NE(looped.find("WHILE [#100 LT 7] DO 1"), std::string::npos) << looped;
  EXPECT_LT(lines_of(looped).size(), lines_of(plain).size() / 2);
  EXPECT_EQ(unrolled(looped), unrolled(plain));
  // Layers that differ (a seam moving along the path) stay as they are.
  s.seam_offset_mm = 37;
  const Toolpath moving = plan_toolpath(TriangleMesh{}, {s}, {});
  EXPECT_EQ(gcode::write_gcode(moving, loop_d, {}).find("WHILE"), std::string::npos);
}

// The looped program run by the macro interpreter commands the plain program's blocks, word for word.
TEST(MacroLoops, TheInterpreterRunsTheLoopIntoThePlainProgram) {
  const SectionParams s = ring(10);
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {s}, {});
  gcode::GcodeDialect d;
  const std::string plain = gcode::write_gcode(tp, d, {});
  d.macro_loops = true;
  const std::string looped = gcode::write_gcode(tp, d, {});
  ASSERT_NE(looped.find("WHILE"), std::string::npos);
  auto blocks = [](const std::string& program) {
    std::vector<std::vector<std::pair<char, double>>> out;
    gcode::MacroProgram(program).run([&](const gcode::Block& b) {
      if (b.words.empty()) return;
      std::vector<std::pair<char, double>> words;
      for (const gcode::Word& w : b.words) words.emplace_back(w.letter, w.value);
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
  const Toolpath tp = plan_toolpath(TriangleMesh{}, {ring(6)}, {});
  gcode::GcodeDialect d;
  const gcode::ReaderOptions ro = gcode::reader_options_for(d, nullptr);
  std::istringstream plain_in(gcode::write_gcode(tp, d, {}));
  d.macro_loops = true;
  std::istringstream looped_in(gcode::write_gcode(tp, d, {}));
  const Toolpath plain = gcode::read_gcode(plain_in, "plain.nc", ro),
                 looped = gcode::read_gcode(looped_in, "looped.nc", ro);
  ASSERT_EQ(looped.moves.size(), plain.moves.size());
  ASSERT_EQ(looped.layers.size(), 6u);
  for (std::size_t i = 0; i < plain.moves.size(); ++i) {
    EXPECT_NEAR((looped.moves[i].end - plain.moves[i].end).norm(), 0.0, 1e-9) << i;
    EXPECT_NEAR(looped.moves[i].volume_mm3, plain.moves[i].volume_mm3, 1e-9) << i;
    EXPECT_EQ(looped.moves[i].source_line > 0, true);
  }
  // An endless loop is an error naming its line, not a hang.
  std::istringstream endless("#1=0\nWHILE [#1 LT 1] DO 1\nG1 X1\nEND 1\nM30\n");
  gcode::ReaderOptions short_run = ro;
  short_run.max_macro_steps = 1000;
  EXPECT_THROW((void)gcode::read_gcode(endless, "endless.nc", short_run), InputError);
}

}  // namespace
}  // namespace beadtwin::slicer
