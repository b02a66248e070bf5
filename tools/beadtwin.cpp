// beadtwin: the command-line program (docs/usage.md, "The command line"). A thin main: parse the command
// line, call the scenario engine, print errors, map outcomes to exit codes:
//   0 ran and every gate passed · 1 ran and a gate failed · 2 bad input or usage · 3 internal error.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "scenarios/input/metrics.hpp"
#include "scenarios/input/params.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "tools/mpi_loader.hpp"
#include "tools/mpi_module.hpp"
#include "tools/sweep_runner.hpp"

namespace {

constexpr int kExitPass = 0;
constexpr int kExitGateFailed = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitInternal = 3;

// Parses every --set KEY=VALUE.
std::vector<beadtwin::scenarios::Setting> settings_of(const std::vector<std::string>& texts) {
  std::vector<beadtwin::scenarios::Setting> out;
  for (const std::string& t : texts) out.push_back(beadtwin::scenarios::parse_setting(t));
  return out;
}

// Loads the scenario (the built-in default without a path), with the command line's settings, and prints
// what its inputs needed repaired.
beadtwin::scenarios::Scenario load(const std::string& path, const std::vector<std::string>& sets) {
  const auto settings = settings_of(sets);
  auto scenario = path.empty() ? beadtwin::scenarios::load_default_scenario(settings)
                               : beadtwin::scenarios::load_scenario(path, settings);
  for (const auto& w : scenario.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return scenario;
}

// Gates from the command line (--gate EXPR, --gates FILE) join the scenario's.
struct ExtraGates {
  std::vector<std::string> exprs;
  std::vector<std::string> files;
};
void add_gates(beadtwin::scenarios::Scenario& scenario, const ExtraGates& extra) {
  for (const std::string& f : extra.files)
    for (auto& g : beadtwin::scenarios::load_gates(f)) scenario.gates.push_back(std::move(g));
  for (const std::string& e : extra.exprs)
    scenario.gates.push_back(beadtwin::scenarios::parse_gate_text(e, {"command line (--gate)", 0, 0}));
}

// A progress bar on a terminal: the variant, the stage, how far it has got and the time it still needs
// (from its pace so far), redrawn in place; the finished stages' lines print above it. Not in CI (the
// CI environment variable) or when standard error is not a terminal: plain lines only.
class ProgressBar {
 public:
  static bool wanted() { return isatty(STDERR_FILENO) != 0 && std::getenv("CI") == nullptr; }

  void update(const std::string& variant, const std::string& stage, double fraction) {
    const auto now = std::chrono::steady_clock::now();
    if (stage != stage_ || variant != variant_) {
      variant_ = variant;
      stage_ = stage;
      start_ = now;
    } else if (now - drawn_ < std::chrono::milliseconds(100) && fraction < 1.0) {
      return;  // at most ten redraws a second
    }
    drawn_ = now;
    constexpr int kWidth = 28;
    const int full = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * kWidth + 0.5);
    std::string bar;
    for (int i = 0; i < kWidth; ++i) bar += i < full ? "█" : "░";
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    std::string eta;
    if (fraction > 0.02 && fraction < 1.0 && elapsed > 0.5) {
      const long left = std::lround(elapsed * (1.0 - fraction) / fraction);
      eta = fmt::format("  ETA {}:{:02}", left / 60, left % 60);
    }
    line_ = fmt::format("[{}] {:<10} {} {:3.0f} %{}", variant_, stage_, bar, 100 * fraction, eta);
    std::fprintf(stderr, "\r\033[K%s", line_.c_str());
    std::fflush(stderr);
  }
  // A finished stage's line, above the bar.
  void print(const std::string& line) {
    std::fprintf(stderr, "\r\033[K%s\n", line.c_str());
    std::fflush(stderr);
    line_.clear();  // the stage is done: the next one's first report draws the bar again
  }
  void clear() {
    if (!line_.empty()) std::fprintf(stderr, "\r\033[K");
    line_.clear();
  }

 private:
  std::string variant_, stage_, line_;
  std::chrono::steady_clock::time_point start_, drawn_;
};

// Runs a loaded scenario and prints the verdict, the report and the images.
int run_and_report(const beadtwin::scenarios::Scenario& scenario, const std::string& out_dir,
                   const std::vector<std::string>& variants, bool quiet,
                   beadtwin::thermal::Communicator* thermal_ranks = nullptr) {
  beadtwin::scenarios::RunOptions options;
  options.out_dir = out_dir;
  options.variants = variants;
  options.thermal_ranks = thermal_ranks;
  ProgressBar bar;
  const bool draw = !quiet && ProgressBar::wanted();
  // Every stage's progress tells the interrupt handler what a Ctrl-C would stop.
  options.progress = [&bar, draw](const std::string& variant, const std::string& stage, double fraction) {
    beadtwin::set_interrupt_context(variant + ": " + stage);
    if (draw) bar.update(variant, stage, fraction);
  };
  if (!quiet) {
    if (draw) {
      options.log = [&bar](const std::string& line) { bar.print(line); };
    } else {
      options.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    }
    std::fprintf(stderr, "beadtwin %s: scenario %s (%s), %zu variant(s)\n", BEADTWIN_VERSION,
                 scenario.name.c_str(), scenario.file.c_str(), scenario.variants.size());
  }
  const auto result = [&] {
    try {
      return beadtwin::scenarios::run_scenario(scenario, options);
    } catch (...) {
      bar.clear();  // the error's message starts a clean line
      throw;
    }
  }();
  bar.clear();
  for (const auto& v : result.variants)
    for (const auto& g : v.gates)
      if (!g.passed) std::fprintf(stderr, "gate failed in %s: %s\n", v.name.c_str(), g.message.c_str());
  const std::filesystem::path dir = std::filesystem::absolute(out_dir);
  std::printf("%s in %.1f s\n", result.passed ? "PASSED" : "FAILED", result.wall_time_s);
  std::printf("report: %s\n", (dir / "report.html").c_str());
  for (const auto& v : result.variants)
    for (const auto& img : v.images) std::printf("image:  %s\n", (dir / img).c_str());
  return result.passed ? kExitPass : kExitGateFailed;
}

int cmd_run(const std::string& scenario_path, const std::vector<std::string>& sets, const ExtraGates& gates,
            const std::string& out_dir, const std::vector<std::string>& variants, bool quiet, int threads) {
  auto scenario = load(scenario_path, sets);
  add_gates(scenario, gates);
  if (!beadtwin::tools::launched_by_mpi()) return run_and_report(scenario, out_dir, variants, quiet);
#ifdef BEADTWIN_MPI_MODULE
  // Under mpirun every rank has loaded the scenario (bad input ends each alike, before MPI starts). Rank 0
  // runs it and writes every output; the others take their share of each thermal solve.
  namespace mpi = beadtwin::tools::mpi;
  mpi::RunJob job;
  job.run = [&](beadtwin::thermal::Communicator& ranks, int on_this_node) {
    // The ranks on a node share its cores (unless --threads said otherwise).
    std::optional<tbb::global_control> share;
    if (threads == 0) {
      const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      share.emplace(tbb::global_control::max_allowed_parallelism,
                    static_cast<std::size_t>(std::max(1, cores / std::max(1, on_this_node))));
    }
    if (ranks.rank() == 0) return run_and_report(scenario, out_dir, variants, quiet, &ranks);
    beadtwin::scenarios::RunOptions options;
    options.out_dir = out_dir;
    options.variants = variants;
    options.thermal_ranks = &ranks;
    return beadtwin::scenarios::share_thermal(scenario, options) ? kExitPass : kExitBadInput;
  };
  job.shared_error = [](std::exception_ptr error) {
    try {
      std::rethrow_exception(error);
    } catch (const beadtwin::InputError&) {
      return true;
    } catch (...) {
      return false;
    }
  };
  return reinterpret_cast<mpi::RunEntry>(beadtwin::tools::mpi_module_entry(mpi::kRunEntryName))(job);
#else
  (void)threads;
  // Each rank would run the whole scenario into the same folder.
  throw beadtwin::InputError(
      {"command line", 0, 0}, "mpirun",
      "this beadtwin was built without MPI, so its ranks cannot share a run: run it "
      "without mpirun, or build beadtwin where MPI is installed (tools/setup.sh does)");
#endif
}

// A print program simulated as it is (docs/usage.md, "The command line"): machine and material given, from a
// scenario, or inferred from the program; with a baseline, both are simulated and compared in the report.
int cmd_check(const beadtwin::scenarios::ProgramCheck& check, const ExtraGates& gates,
              const std::string& out_dir, bool quiet) {
  auto scenario = beadtwin::scenarios::load_program_check(check);
  add_gates(scenario, gates);
  for (const auto& w : scenario.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return run_and_report(scenario, out_dir, {}, quiet);
}

int cmd_slice(const std::string& scenario_path, const std::vector<std::string>& sets,
              const std::string& variant, const std::string& out) {
  const auto scenario = load(scenario_path, sets);
  if (out != "-") {
    const std::filesystem::path parent = std::filesystem::absolute(out).parent_path();
    beadtwin::prepare_output_dir(parent, "--out");
  }
  const std::string program = beadtwin::scenarios::slice_program(scenario, variant);
  if (out == "-") {
    std::fwrite(program.data(), 1, program.size(), stdout);
  } else {
    beadtwin::write_file_atomic(out, program);
    std::printf("program: %s\n", std::filesystem::absolute(out).c_str());
  }
  return kExitPass;
}

// What beadtwin reads in a program, without simulating it: layers, moves, material and print time on the
// machine (given or inferred).
int cmd_read(const beadtwin::scenarios::ProgramCheck& check) {
  const auto scenario = beadtwin::scenarios::load_program_check(check);
  for (const auto& w : scenario.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const auto& v = scenario.variants.front();
  const beadtwin::Toolpath& tp = *v.program;  // timed without a copy: only its total time is printed
  const double time_s = beadtwin::motion_time_s(tp, v.machine.motion);
  std::printf(
      "%s\nmachine: %s\nlayers: %zu\nmoves: %zu\nprint length: %.1f mm\ntravel length: %.1f mm\n"
      "commanded volume: %.1f mm3\nprint time: %.1f s\n",
      v.program_summary.c_str(), v.machine.name.c_str(), tp.layers.size(), tp.moves.size(),
      tp.print_length_mm(), tp.travel_length_mm(), tp.commanded_volume_mm3(), time_s);
  return kExitPass;
}

// A subcommand that prints a table generated from the declarations, as Markdown: docs/parameters.md and
// docs/metrics.md are their output.
struct TableCommand {
  CLI::App* command;
  std::string (*markdown)();
};

std::vector<TableCommand> add_table_commands(CLI::App& app) {
  return {
      {app.add_subcommand(
           "params",
           "List every scenario parameter (key, type, default, range, meaning, source) as Markdown."),
       beadtwin::scenarios::params_markdown},
      {app.add_subcommand("metrics",
                          "List every metric a run measures (name, unit, which way is better, whether gates "
                          "may use it, meaning) as Markdown."),
       beadtwin::scenarios::metrics_markdown}};
}

int cmd_print(const std::string& text) {
  std::fwrite(text.data(), 1, text.size(), stdout);
  return kExitPass;
}

// Help texts that several subcommands share.
constexpr const char* kThreadsHelp =
    "Use at most N threads (default: every core); results do not depend on it";
constexpr const char* kGateHelp =
    "A gate over the report's metrics (beadtwin metrics lists them), absolute or relative to the baseline "
    "variant: 'porosity < 0.03', 'print_time_s <= baseline * 1.05'; repeat for several";
constexpr const char* kGatesHelp =
    "A YAML file of gates (a list, or a scenario's gates:), added to the others";
constexpr const char* kSetHelp =
    "Set a parameter for every variant, after the variants' own settings: KEY=VALUE, KEY as a variant's "
    "set: takes it (sections.walls.speed=1.2in/s, render.width=1920); repeat for several";

// What the command line says, for whichever subcommand it names.
struct CommandLine {
  std::string scenario_path, out_dir = "beadtwin-out", variant, program_out;
  std::vector<std::string> variants, sets;
  ExtraGates gates;
  bool quiet = false;
  int threads = 0;
  beadtwin::scenarios::ProgramCheck check;
  std::string check_program, check_baseline, check_scenario;
  beadtwin::tools::SweepCommand sweep;
  CLI::App *run = nullptr, *slice = nullptr, *check_cmd = nullptr, *read_cmd = nullptr, *sweep_cmd = nullptr;
  std::vector<TableCommand> tables;
};

// beadtwin run and beadtwin slice.
void add_run_and_slice(CLI::App& app, CommandLine& c) {
  c.run =
      app.add_subcommand("run", "Run the whole pipeline on a scenario and write reports, images, programs.");
  c.run->add_option("scenario", c.scenario_path,
                    "Scenario YAML file (default: the built-in LSAM open-box scenario)");
  c.run
      ->add_option("-o,--out", c.out_dir,
                   "Output directory (report.json, report.html, junit.xml, summary.md, per-variant files)")
      ->capture_default_str();
  c.run->add_option("--variant", c.variants, "Run only this variant (repeat for several)");
  c.run->add_option("--set", c.sets, kSetHelp);
  c.run->add_option("--gate", c.gates.exprs, kGateHelp);
  c.run->add_option("--gates", c.gates.files, kGatesHelp);
  c.run->add_flag("-q,--quiet", c.quiet, "Print only the verdict and the report path");
  c.run->add_option("--threads", c.threads, kThreadsHelp)->check(CLI::Range(1, 1024));

  c.slice = app.add_subcommand("slice", "Slice a scenario's part and write only the print program.");
  c.slice->add_option("scenario", c.scenario_path, "Scenario YAML file (default: the built-in scenario)");
  c.slice->add_option("--variant", c.variant, "Variant to slice (default: the first)");
  c.slice->add_option("--set", c.sets, kSetHelp);
  c.slice->add_option("-o,--out", c.program_out, "Print program file to write, or - for standard output")
      ->required();
}

// beadtwin check and beadtwin read.
void add_check_and_read(CLI::App& app, CommandLine& c) {
  c.check_cmd = app.add_subcommand(
      "check", "Simulate a print program from any slicer (or a Fanuc macro program) as it is written.");
  c.check_cmd->add_option("program", c.check_program, "G-code program to simulate")->required();
  c.check_cmd->add_option(
      "--machine", c.check.machine,
      "Machine by name (machines/NAME.yaml or shipped); default: inferred from the program");
  c.check_cmd->add_option("--material", c.check.material, "Material by name; default: cf-abs-20");
  c.check_cmd->add_option("--scenario", c.check_scenario,
                          "Take machine, material, units, output, thermal and gates from this scenario");
  c.check_cmd->add_option("--baseline", c.check_baseline,
                          "An older program: simulated beside this one, differences in the report");
  c.check_cmd->add_option("--set", c.sets, kSetHelp);
  c.check_cmd->add_option("--gate", c.gates.exprs, kGateHelp);
  c.check_cmd->add_option("--gates", c.gates.files, kGatesHelp);
  c.check_cmd->add_option("-o,--out", c.out_dir, "Output directory")->capture_default_str();
  c.check_cmd->add_flag("-q,--quiet", c.quiet, "Print only the verdict and the report path");
  c.check_cmd->add_option("--threads", c.threads, kThreadsHelp)->check(CLI::Range(1, 1024));

  c.read_cmd = app.add_subcommand(
      "read", "Read a print program and print what beadtwin sees in it (layers, moves, material, time).");
  c.read_cmd->add_option("program", c.check_program, "G-code program to read")->required();
  c.read_cmd->add_option("--machine", c.check.machine, "Machine by name; default: inferred from the program");
}

// beadtwin sweep.
void add_sweep(CLI::App& app, CommandLine& c) {
  c.sweep_cmd = app.add_subcommand(
      "sweep",
      "Run a scenario's variant over a grid of parameter values and report them side by side: a table "
      "sorted by a metric, the Pareto front of two, the gates applied to each. Under mpirun, rank 0 hands "
      "the variants out to the other ranks.");
  c.sweep_cmd->add_option("scenario", c.sweep.scenario,
                          "Scenario YAML file (default: the built-in scenario)");
  c.sweep_cmd->add_option("--variant", c.sweep.base_variant,
                          "The scenario's variant the settings change (default: the first)");
  c.sweep_cmd->add_option(
      "--set", c.sweep.sets,
      "KEY=V1,V2,...: the values of one parameter; every combination of the --set options is a variant "
      "(KEY as a variant's set: takes it; commas inside [] or {} do not split); repeat for each parameter");
  c.sweep_cmd->add_option("--combinations", c.sweep.combinations,
                          "A YAML file listing combinations, each a map {KEY: VALUE, ...}; with --set, each "
                          "is crossed with the --set grid");
  c.sweep_cmd->add_option("--sort", c.sweep.sort,
                          "Sort the table by this metric, METRIC or METRIC:max when larger is better "
                          "(default: the first --pareto metric, else print_time_s)");
  c.sweep_cmd->add_option("--pareto", c.sweep.pareto,
                          "Plot the Pareto front of two metrics X,Y (each METRIC or METRIC:max), such as "
                          "print_time_s,interfaces.too_cold_fraction");
  c.sweep_cmd->add_option("--gate", c.sweep.gate_exprs, kGateHelp);
  c.sweep_cmd->add_option("--gates", c.sweep.gate_files, kGatesHelp);
  c.sweep_cmd
      ->add_option("-o,--out", c.sweep.out_dir,
                   "Output directory: sweep.html, sweep.json, summary.md, junit.xml, and each variant's "
                   "run in variants/NAME/; a sweep started again here keeps the variants that ran")
      ->capture_default_str();
  c.sweep_cmd
      ->add_option("-j,--jobs", c.sweep.jobs,
                   "Variants at once on this machine (default 1; under mpirun each rank runs one)")
      ->check(CLI::Range(1, 1024));
  c.sweep_cmd
      ->add_option("--threads", c.sweep.threads,
                   "Threads for each variant (default: the cores over the variants running at once)")
      ->check(CLI::Range(1, 1024));
  c.sweep_cmd->add_flag("-q,--quiet", c.sweep.quiet, "Print only the verdict and the report path");
}

// Runs the subcommand the command line named.
int dispatch(CommandLine& c) {
  if (*c.run) return cmd_run(c.scenario_path, c.sets, c.gates, c.out_dir, c.variants, c.quiet, c.threads);
  if (*c.slice) return cmd_slice(c.scenario_path, c.sets, c.variant, c.program_out);
  c.check.program = c.check_program;
  if (*c.read_cmd) return cmd_read(c.check);
  if (*c.check_cmd) {
    c.check.baseline = c.check_baseline;
    c.check.scenario = c.check_scenario;
    c.check.settings = settings_of(c.sets);
    return cmd_check(c.check, c.gates, c.out_dir, c.quiet);
  }
  if (*c.sweep_cmd) return beadtwin::tools::run_sweep(c.sweep);
  for (const TableCommand& t : c.tables)
    if (*t.command) return cmd_print(t.markdown());
  return kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "beadtwin — process simulator and digital twin for large-format additive manufacturing.\n"
      "Slices a part into sections, deposits the toolpath into a voxel model, simulates layer cooling\n"
      "and interlayer fusion, renders the predicted part and writes reports with a pass/fail exit code.\n\n"
      "Exit codes: 0 ran and every gate passed, 1 a gate failed, 2 bad input or usage, 3 internal error."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("beadtwin ") + BEADTWIN_VERSION);

  CommandLine c;
  add_run_and_slice(app, c);
  add_check_and_read(app, c);
  add_sweep(app, c);
  c.tables = add_table_commands(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    (void)app.exit(e);
    return kExitBadInput;
  }

  beadtwin::install_interrupt_handler();
  beadtwin::set_interrupt_context("loading the input");
  // The TBB thread pool's limit for the whole run (deposit, thermal vectors, rendering).
  std::optional<tbb::global_control> thread_limit;
  if (c.threads > 0) thread_limit.emplace(tbb::global_control::max_allowed_parallelism, c.threads);

  try {
    return dispatch(c);
  } catch (const beadtwin::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const beadtwin::InternalError& e) {
    std::fprintf(stderr, "internal error (a bug in beadtwin, please report it): %s\n", e.what());
    return kExitInternal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "internal error: %s\n", e.what());
    return kExitInternal;
  }
}
