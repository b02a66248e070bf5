// Scenarios: a part, a machine, a material, sections with their print parameters, variants that
// override parameters, and gates. Loading validates everything before any heavy work starts and reports
// problems with file, line, column and key.
#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.hpp"
#include "core/error.hpp"
#include "core/flow.hpp"
#include "core/material.hpp"
#include "core/toolpath.hpp"
#include "gcode/dialect.hpp"
#include "render/camera.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"
#include "thermal/fusion.hpp"

namespace beadtwin::scenarios {

// What flattens the bead, and so how the machine lays it: a roller following the nozzle, a tamper, or
// neither (a robot cell's or a desktop printer's round bead).
enum class MachineKind : std::uint8_t { kRollerGantry, kTamperGantry, kRobot, kDesktop };
inline constexpr EnumName<MachineKind> kMachineKindNames[] = {{MachineKind::kRollerGantry, "roller-gantry"},
                                                              {MachineKind::kTamperGantry, "tamper-gantry"},
                                                              {MachineKind::kRobot, "robot"},
                                                              {MachineKind::kDesktop, "desktop"}};
constexpr std::span<const EnumName<MachineKind>> enum_names(MachineKind) {
  return kMachineKindNames;
}

// A machine as a machine file describes it (machine_params(): its keys, defaults and meanings). The defaults
// are those of the declaration: an LSAM-class gantry with a gear pump, programs in inches.
struct Machine {
  std::string name;
  std::string description = "-";
  MachineKind kind = MachineKind::kRollerGantry;
  MotionLimits motion{.max_feed_mm_s = 20 * kMmPerInch,
                      .max_travel_mm_s = 40 * kMmPerInch,
                      .acceleration_mm_s2 = 40 * kMmPerInch,
                      .junction_deviation_mm = 0.02 * kMmPerInch};
  double roller_width_mm = 0.0;                             // 0: unknown
  double roller_diameter_mm = 0.0;                          // 0: unknown
  double roller_pressure_Pa = 0.0;                          // 0: no roller load on the bead
  double roller_contact_mm = 0.0;                           // length along the bead it presses
  double nozzle_diameter_mm = 0.0;                          // 0: unknown
  double ooze_time_s = 0.0;                                 // 0: no ooze after melt off
  double extruder_output_kg_s = 150 * kKgPerLb / 3600;      // nominal output (a Thermwood PH15 head)
  double extruder_max_output_kg_s = 200 * kKgPerLb / 3600;  // most it delivers
  Extruder extruder;  // its max flow is set from max_output once the material's density is known
  Environment environment;
  gcode::GcodeDialect dialect{.inches = true};
  long macro_step_limit = 10'000'000;  // statements a macro program may run (gcode.macro_step_limit)
  // G0 runs at the machine's max travel speed whatever its F, as CNC controllers run it: the dialect's
  // rapid feed is set from it.
  bool rapid_g0 = false;

  // Whether a roller or a tamper flattens the bead.
  bool flattens() const { return kind == MachineKind::kRollerGantry || kind == MachineKind::kTamperGantry; }
};

// A tool / melt configuration (patent (48)): the bead a section lays when it names the tool.
struct Tool {
  std::string description = "-";
  double bead_width_mm = 0.0;
  double bead_thickness_mm = 0.0;
};

struct PartSpec {
  enum class Kind { kNone, kMesh, kBox, kOpenBox };
  Kind kind = Kind::kOpenBox;
  std::filesystem::path mesh;                          // kMesh: resolved path
  double mesh_scale = 1.0;                             // mesh file units to mm
  std::shared_ptr<const slicer::TriangleMesh> loaded;  // the part as a mesh, made or read once when loading
  Eigen::Vector3d size = Eigen::Vector3d::Zero();      // kBox, kOpenBox: outer size, mm
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();    // minimum corner, mm
  std::vector<slicer::WallTier> tiers;                 // kOpenBox: wall thickness from the floor up
  double floor_mm = 0.0;                               // kOpenBox
  std::string describe() const;
};

// What a picture colours the part by (render.images[].colour).
enum class Colouring {
  kFusion,       // each bead piece by its worst interface's verdict
  kSection,      // by section
  kLayer,        // by toolpath layer
  kTime,         // by deposition time
  kSubstrate,    // by the temperature of what each bead piece landed on, as it landed
  kSurface,      // by the surface temperature of what it landed on: a thermal camera's, just before covered
  kHealing,      // by each bead piece's least degree of healing
  kDeviation,    // by the stock over the CAD (needs a part mesh)
  kPorosity,     // by the local void fraction around the surface
  kTemperature,  // by the temperature at a moment (render.images[].time)
};

inline constexpr EnumName<Colouring> kColouringNames[] = {
    {Colouring::kFusion, "fusion"},       {Colouring::kSection, "section"},
    {Colouring::kLayer, "layer"},         {Colouring::kTime, "time"},
    {Colouring::kSubstrate, "substrate"}, {Colouring::kSurface, "surface"},
    {Colouring::kHealing, "healing"},     {Colouring::kDeviation, "deviation"},
    {Colouring::kPorosity, "porosity"},   {Colouring::kTemperature, "temperature"}};
constexpr std::span<const EnumName<Colouring>> enum_names(Colouring) {
  return kColouringNames;
}
// The colouring's name in scenario files ("fusion", "substrate", ...).
inline std::string_view to_string(Colouring colouring) {
  return name_of(colouring);
}

// A plane through the part: the half the normal points into is cut away, so the inside shows.
struct CutSpec {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // mm
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
};

// One picture of a variant (render.images).
struct ImageSpec {
  std::string name;  // file stem, unique among a variant's images
  Colouring colour = Colouring::kFusion;
  render::CameraSpec camera;
  std::optional<CutSpec> cut;
  int up_to_layer = -1;  // >= 0: the part as it stood when this toolpath layer was done
  double time_s = std::numeric_limits<double>::infinity();  // kTemperature: when; infinity: end of print
  std::optional<std::pair<double, double>> range;           // the colour scale's ends; default: the data's
};

// A frame per layer (or per `every` layers) as the part grows (render.progress).
struct ProgressSpec {
  Colouring colour = Colouring::kLayer;
  render::CameraSpec camera;
  int every = 1;
};

// Pictures (the render: block).
struct RenderSpec {
  int width = 1280;
  int height = 800;
  int samples = 8;  // per pixel
  bool ambient_occlusion = true;
  bool exr = false;    // each picture also as EXR with the raw field values
  bool sheet = true;   // a comparison sheet of the variants' pictures, side by side
  bool legend = true;  // title, legend and scale bar on each picture
  std::vector<ImageSpec> images;
  bool images_given = false;  // images come from the scenario (else the default set)
  std::optional<ProgressSpec> progress;
};

struct OutputSpec {
  double voxel_size_mm = 0.0;
  SourceLocation voxel_size_at;     // where it was set, for messages found when depositing
  double memory_budget_gb = 0.0;    // 0: automatic
  std::string skin_format = "ply";  // file type of the as-printed skin, ply or stl; empty: not written
  double skin_adaptivity = 0.0;     // 0..1 (sim::extract_skin)
  double skin_tolerance_mm = 0.3;   // simplification tolerance (sim::extract_skin)
  bool write_fields = false;        // fields.vtu for ParaView (output.fields: vtu; off by default: large)
  // Toolpath layers (from 0) whose mean temperature against time the report keeps; those the print does not
  // reach are left out when it runs.
  std::vector<int> history_layers = {0, 14, 29};
};

// The thermal model's resolution and integration (thermal/mesh.hpp, thermal/heat.hpp).
struct ThermalSpec {
  int cells_across = 3;
  int cells_through = 1;
  double cell_length_mm = 0.0;    // 0: two bead widths
  double birth_interval_s = 0.0;  // 0: chosen from the cells
  double sample_interval_s = 5.0;
  double cooldown_s = 600.0;
  double max_cooldown_s = 24.0 * 3600.0;  // healing goes on while interfaces are warm, up to this
  double rel_tol = 1e-3;
  double abs_tol_k = 0.05;
  bool lump = true;          // settled cells lumped (thermal::HeatOptions::lump)
  bool view_factors = true;  // radiation with each face's view of the sky (thermal::HeatOptions)
  // The verdicts' bands over the inputs' plausible ranges (thermal/uncertainty.hpp).
  // Off by default: the bands cost one more heat solve per heat input (docs/physics.md).
  thermal::UncertaintyMethod uncertainty = thermal::UncertaintyMethod::kOff;
  double uncertainty_tolerance = 1.0;  // the bands' extra solves' tolerances, as factors on rel_tol, abs_tol
  // Temperature snapshots, s; +infinity: the end of the print.
  std::vector<double> snapshot_times_s;
};

// One parameter set, fully resolved: what a run needs, nothing more.
struct Variant {
  std::string name;
  std::map<std::string, std::string> overrides;  // key path -> value text, as the variant set them
  Machine machine;
  Material material;
  PartSpec part;
  std::vector<slicer::SectionParams> sections;
  OutputSpec output;
  RenderSpec render;
  ThermalSpec thermal;
  // A print program to simulate instead of slicing (`program:`, `beadtwin check`): read with the machine's
  // dialect, untimed until the run times it with the machine's motion.
  std::shared_ptr<const Toolpath> program;
  std::filesystem::path program_file;
  std::string program_summary;  // what the reader saw (layers, lines, warnings), for the report
  // The files the variant was built from besides the scenario's own text: its machine and material files
  // (a shipped one as <built-in>/machines/NAME.yaml), its part's mesh and its program.
  std::vector<std::string> input_files;
};

enum class GateOp { kLess, kLessEqual, kGreater, kGreaterEqual, kEqual, kNotEqual };

struct Gate {
  std::string expr;    // as written
  std::string metric;  // dotted metric path ("interfaces.too_cold_fraction")
  GateOp op = GateOp::kLess;
  double threshold = 0.0;
  // Relative to the baseline variant ("print_time_s <= baseline * 1.05"): the threshold is the baseline's
  // value of the same metric times `factor` plus `offset`.
  bool relative = false;
  double factor = 1.0;
  double offset = 0.0;
  SourceLocation where;
};

struct Scenario {
  std::string name;
  std::string description = "-";
  std::string file;     // where it was read from ("<built-in default>" for the embedded one)
  bool inches = false;  // the file writes lengths in inches (units: {length: in}): scale bars follow
  std::vector<Variant> variants;
  std::vector<Gate> gates;
  std::vector<std::string>
      warnings;  // things repaired or doubtful in the inputs (mesh repairs), for the user
};

// The files every variant of `sc` was built from besides the scenario's text (Variant::input_files).
std::set<std::string> input_files(const Scenario& sc);
// A stable 64-bit digest (FNV-1a, 16 hex digits) of the names and contents of `files` as input_files names
// them: a shipped file's text, any other file's bytes (a file that cannot be read counts by its name alone).
// Equal digests mean the same inputs; a sweep resumes only with them (docs/scaling.md).
std::string contents_digest(const std::set<std::string>& files);

// A parameter set on the command line (`--set KEY=VALUE`): for every variant, after the variant's own
// settings. KEY is a path as a variant's `set:` takes it; VALUE is YAML (`1.2 in/s`, `[0, 5]`, `none`).
struct Setting {
  std::string key;
  std::string value;
};
// Parses "KEY=VALUE"; throws InputError (key "--set") when there is no '=' or no key.
Setting parse_setting(const std::string& text);

// Loads and validates a scenario file. Machine and material given by name are looked up as
// <scenario dir>/machines/NAME.yaml (materials/NAME.yaml), then among the files shipped with beadtwin.
Scenario load_scenario(const std::filesystem::path& path, const std::vector<Setting>& settings = {});
// Loads scenario text (for the embedded default and for tests); `file` is used in messages and to resolve
// relative paths (may be empty).
Scenario load_scenario_text(const std::string& text, const std::string& file,
                            const std::vector<Setting>& settings = {});
// The built-in default scenario (embedded in the binary).
Scenario load_default_scenario(const std::vector<Setting>& settings = {});

// A gate written as text ("porosity < 0.03", "print_time_s <= baseline * 1.05"); `at` says where, for
// messages. Throws InputError (key "gates") for an unknown metric, no comparison or a bad right-hand side.
Gate parse_gate_text(const std::string& expr, const SourceLocation& at);
// The gates of a file: a YAML list of gates, or a scenario's `gates:` list.
std::vector<Gate> load_gates(const std::filesystem::path& path);

// Throws InputError (key "gates") for a gate on a section no variant of `sc` has, naming the sections.
void check_gate_sections(const Scenario& sc);

}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {

// `beadtwin check PROGRAM`: a scenario that simulates a print program instead of slicing a part.
struct ProgramCheck {
  std::filesystem::path program;
  std::filesystem::path baseline;  // optional: an older program, simulated beside it and compared
  std::string machine, material;   // names (shipped or beside the scenario) or files; empty: inferred
  std::filesystem::path scenario;  // optional: machine, material, units, output, thermal and gates from it
  std::vector<Setting> settings;   // --set, for every variant
};

// The machine a program was written for, guessed from its first megabyte: E words mean a filament
// printer (desktop-fff); otherwise a pellet gantry (lsam-ph15). `why` says what decided it.
std::string infer_machine(const std::filesystem::path& program, std::string* why);

// The filament type a program says it was sliced for ("; filament_type = PLA" in the settings PrusaSlicer
// and Slic3r write at its end; the first of several extruders'), as written; empty when it says none.
std::string stated_filament_type(const std::filesystem::path& program);

// Loads the scenario for a program check: variant "program" (and "baseline" with an older program), with
// the machine and material given, taken from the scenario, or inferred (the material from the program's
// filament type when a shipped material has its name, as pla and abs do; else cf-abs-20); what was assumed is
// in the scenario's warnings.
Scenario load_program_check(const ProgramCheck& check);

}  // namespace beadtwin::scenarios
