// `beadtwin check PROGRAM`: the scenario that simulates a print program, with what it can guess of the
// machine and the material from the program's text.
#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "gcode/program_reader.hpp"
#include "gcode/reader_options.hpp"
#include "scenarios/input/embedded.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/input/scenario_blocks.hpp"
#include "scenarios/input/yaml_reader.hpp"

namespace beadtwin::scenarios {

namespace {

// The program a check reads, open for the guesses made from its text before it is read.
std::ifstream open_program(const std::filesystem::path& program) {
  if (is_special_file(program)) throw InputError({program.string(), 0, 0}, "program", "not a regular file");
  std::ifstream in(program, std::ios::binary);
  if (!in) throw InputError({program.string(), 0, 0}, "program", "cannot open the program");
  return in;
}

}  // namespace

std::string infer_machine(const std::filesystem::path& program, std::string* why) {
  std::ifstream in = open_program(program);
  std::string text(std::size_t{1} << 20, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  std::istringstream lines(text);
  int e_words = 0, melt_codes = 0;
  for (std::string line; std::getline(lines, line);) {
    const std::string code = line.substr(0, line.find_first_of(";("));
    if ((code.rfind("G1", 0) == 0 || code.rfind("G0", 0) == 0) && code.find(" E") != std::string::npos)
      ++e_words;
    if (code.rfind("M23", 0) == 0 || code.rfind("M24", 0) == 0) ++melt_codes;
  }
  if (e_words > melt_codes) {
    if (why) *why = fmt::format("{} moves with E words: a filament printer", e_words);
    return "desktop-fff";
  }
  if (why)
    *why = melt_codes > 0 ? fmt::format("{} M23/M24 melt codes and no E words: a pellet gantry", melt_codes)
                          : std::string("no E words: a pellet gantry");
  return "lsam-ph15";
}

std::string stated_filament_type(const std::filesystem::path& program) {
  std::ifstream in = open_program(program);
  std::string type = gcode::stated_setting(in, "filament_type").value_or("");
  type = type.substr(0, type.find(';'));  // several extruders: "PLA;PETG", the first taken
  while (!type.empty() && type.back() == ' ') type.pop_back();
  return type;
}

Scenario load_program_check(const ProgramCheck& check) {
  std::vector<std::string> assumed;
  YAML::Node doc(YAML::NodeType::Map);
  std::string file = "<check>";
  if (!check.scenario.empty()) {
    // Machine, material, units, output, render, thermal and gates from the scenario; its part and sections
    // are not used.
    file = check.scenario.string();
    const std::string text = read_text_file(check.scenario, {file, 0, 0}, {});
    YAML::Node base;
    try {
      base = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw InputError({file, e.mark.line + 1, e.mark.column + 1}, {}, e.msg);
    }
    for (const char* key : {"units", "machine", "material", "output", "render", "thermal", "gates"})
      if (base[key]) doc[key] = base[key];
  }
  doc["name"] = "check " + check.program.filename().string();
  if (!doc["units"]) doc["units"] = YAML::Load("{length: mm}");
  if (!check.machine.empty()) {
    doc["machine"] = check.machine;
  } else if (!doc["machine"]) {
    std::string why;
    doc["machine"] = infer_machine(check.program, &why);
    assumed.push_back(
        fmt::format("assumed machine {} ({}); give --machine to choose", doc["machine"].Scalar(), why));
  }
  if (!check.material.empty()) {
    doc["material"] = check.material;
  } else if (!doc["material"]) {
    // The filament a desktop slicer says it sliced for, where the shipped library has a material of that
    // name; else the shipped CF-ABS.
    const std::string type = stated_filament_type(check.program);
    std::string lower = type;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (!lower.empty() && shipped_files().contains("materials/" + lower + ".yaml")) {
      doc["material"] = lower;
      assumed.push_back(
          fmt::format("assumed material {} (the program says filament_type = {}); give --material to choose",
                      lower, type));
    } else {
      doc["material"] = "cf-abs-20";
      assumed.push_back(
          type.empty() ? std::string("assumed material cf-abs-20 (the shipped material); give --material to "
                                     "choose")
                       : fmt::format("assumed material cf-abs-20 (the shipped material): the program's "
                                     "filament_type {} is not one beadtwin ships; give --material to choose",
                                     type));
    }
  }
  doc["program"] = std::filesystem::absolute(check.program).string();
  YAML::Node variants(YAML::NodeType::Sequence);
  YAML::Node program_variant(YAML::NodeType::Map);
  program_variant["name"] = "program";
  variants.push_back(program_variant);
  if (!check.baseline.empty()) {
    YAML::Node baseline(YAML::NodeType::Map);
    baseline["name"] = "baseline";
    baseline["set"]["program"] = std::filesystem::absolute(check.baseline).string();
    variants.push_back(baseline);
  }
  doc["variants"] = variants;
  YAML::Emitter out;
  out << doc;
  Scenario sc = load_scenario_text(out.c_str(), file, check.settings);
  sc.warnings.insert(sc.warnings.begin(), assumed.begin(), assumed.end());
  return sc;
}

}  // namespace beadtwin::scenarios
