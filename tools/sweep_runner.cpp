#include "tools/sweep_runner.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sched.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/memory.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/sweep.hpp"
#include "tools/mpi_loader.hpp"
#include "tools/mpi_module.hpp"

namespace beadtwin::tools {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using scenarios::Setting;
using scenarios::SweepPoint;
using scenarios::SweepRecord;
using Clock = std::chrono::steady_clock;

const SourceLocation kCommandLine{"command line", 0, 0};

// How one variant is run, the same for all: the `beadtwin run` command before its settings, the sweep's
// output folder, and whether the run's memory budget is shared out among the variants running beside it
// on one machine (the scenario leaves it automatic).
struct RunSpec {
  std::vector<std::string> command;  // beadtwin run [SCENARIO] --variant BASE -q
  fs::path out_dir;                  // absolute
  bool share_memory = false;
};

json spec_json(const RunSpec& s) {
  return {{"command", s.command}, {"out_dir", s.out_dir.string()}, {"share_memory", s.share_memory}};
}
RunSpec spec_of(const json& j) {
  return {j.at("command").get<std::vector<std::string>>(), fs::path(j.at("out_dir").get<std::string>()),
          j.at("share_memory").get<bool>()};
}

fs::path variant_dir(const RunSpec& spec, const std::string& name) {
  return spec.out_dir / "variants" / name;
}

// A variant's run as a process of its own: its output and errors go to log.txt in its folder.
struct Launched {
  pid_t pid = -1;
  Clock::time_point start;
};

Launched launch(const RunSpec& spec, const SweepPoint& point, int threads, int sharing) {
  const fs::path dir = variant_dir(spec, point.name);
  fs::create_directories(dir);
  std::vector<std::string> args = spec.command;
  for (const Setting& s : point.settings) args.insert(args.end(), {"--set", s.key + "=" + s.value});
  const bool own_budget = std::any_of(point.settings.begin(), point.settings.end(),
                                      [](const Setting& s) { return s.key == "output.memory_budget"; });
  if (spec.share_memory && sharing > 1 && !own_budget)
    args.insert(args.end(),
                {"--set", fmt::format("output.memory_budget={:.3f}", memory_budget_bytes() / sharing / 1e9)});
  args.insert(args.end(), {"-o", dir.string(), "--threads", std::to_string(std::max(1, threads))});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = (dir / "log.txt").string();
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, STDIN_FILENO);
  Launched l;
  l.start = Clock::now();
  // A variant runs plainly, also when a rank of an MPI job starts it: without the job's environment it does
  // not take itself for a rank (beadtwin run would share its thermal solve with ranks that are not there).
  std::vector<char*> env = environment_without_mpi();
  const int err = posix_spawn(&l.pid, argv[0], &actions, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0)
    throw InternalError(
        fmt::format("cannot start {} for variant {}: {}", argv[0], point.name, std::strerror(err)));
  return l;
}

// The exit code of a wait status; -1 when the process was killed by a signal.
int exit_code_of(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A file's whole text (empty when it cannot be read).
std::string read_whole(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

SweepRecord finish(const RunSpec& spec, const SweepPoint& point, const Launched& l, int status,
                   const std::string& worker) {
  const fs::path dir = variant_dir(spec, point.name);
  SweepRecord r = scenarios::record_of_run(point, dir, exit_code_of(status), read_whole(dir / "log.txt"));
  if (WIFSIGNALED(status))
    r.message = fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status))) +
                (r.message.empty() ? "" : "\n" + r.message);
  r.wall_time_s = std::chrono::duration<double>(Clock::now() - l.start).count();
  r.worker = worker;
  return r;
}

// The record of a variant that could not be started.
SweepRecord not_started(const SweepPoint& point, const std::string& why, const std::string& worker) {
  SweepRecord r;
  r.name = point.name;
  r.settings = point.settings;
  r.message = why;
  r.worker = worker;
  return r;
}

// Runs one variant and waits for it (an MPI worker's way).
SweepRecord run_point(const RunSpec& spec, const SweepPoint& point, int threads, int sharing,
                      const std::string& worker) {
  Launched l;
  try {
    l = launch(spec, point, threads, sharing);
  } catch (const std::exception& e) {
    return not_started(point, e.what(), worker);
  }
  int status = 0;
  while (waitpid(l.pid, &status, 0) < 0)
    if (errno != EINTR)
      throw InternalError(fmt::format("waiting for variant {}: {}", point.name, std::strerror(errno)));
  return finish(spec, point, l, status, worker);
}

// A stable 64-bit hash (FNV-1a) of what decides the variants' results beyond their settings: the scenario's
// text, the base variant, the program's version and the digest of the files the variants are built from
// (machines, materials, meshes, programs: scenarios::contents_digest). A sweep resumes only the records of
// the same plan.
std::string plan_key(const std::string& scenario_text, const std::string& base, const std::string& inputs) {
  return Fnv1a().add(scenario_text + '\0' + base + '\0' + BEADTWIN_VERSION + '\0' + inputs).hex();
}

// Everything decided before the first variant runs.
struct Plan {
  RunSpec spec;
  std::vector<SweepPoint> points;
  scenarios::SweepResult result;  // the description; its records come later
  std::string key;                // plan_key
};

Plan make_plan(const SweepCommand& c) {
  Plan p;
  std::vector<scenarios::SweepAxis> axes;
  for (const std::string& s : c.sets) axes.push_back(scenarios::parse_sweep_axis(s));
  std::vector<std::vector<Setting>> rows;
  if (!c.combinations.empty()) rows = scenarios::load_sweep_combinations(c.combinations);
  if (axes.empty() && rows.empty())
    throw InputError(kCommandLine, "--set",
                     "nothing to sweep: give --set KEY=V1,V2,... (repeat for more parameters) or "
                     "--combinations FILE");

  const auto load = [&](const std::vector<Setting>& settings) {
    return c.scenario.empty() ? scenarios::load_default_scenario(settings)
                              : scenarios::load_scenario(c.scenario, settings);
  };
  scenarios::Scenario sc = load({});
  for (const auto& w : sc.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  std::string base = c.base_variant.empty() ? sc.variants.front().name : c.base_variant;
  const auto variant = std::find_if(sc.variants.begin(), sc.variants.end(),
                                    [&](const scenarios::Variant& v) { return v.name == base; });
  if (variant == sc.variants.end()) {
    std::vector<std::string> names;
    for (const auto& v : sc.variants) names.push_back(v.name);
    throw InputError(kCommandLine, "--variant",
                     fmt::format("scenario '{}' has no variant named '{}'; it has: {}", sc.name, base,
                                 fmt::join(names, ", ")));
  }
  for (const std::string& f : c.gate_files)
    for (auto& g : scenarios::load_gates(f)) sc.gates.push_back(std::move(g));
  for (const std::string& e : c.gate_exprs)
    sc.gates.push_back(scenarios::parse_gate_text(e, {"command line (--gate)", 0, 0}));
  scenarios::check_gate_sections(sc);

  // Every value is checked before anything runs: each axis's values one at a time, and each combination,
  // so a typo stops the sweep at once with the scenario's own message. (Settings that are good alone but
  // not together show as that variant's failure.)
  // The files they are built from (a value may name another machine or material) go into the plan's key.
  std::set<std::string> inputs;
  const auto add_inputs = [&inputs](const scenarios::Scenario& s) {
    inputs.merge(scenarios::input_files(s));
  };
  add_inputs(sc);
  for (const scenarios::SweepAxis& a : axes)
    for (const std::string& v : a.values) add_inputs(load({{a.key, v}}));
  for (const auto& row : rows) add_inputs(load(row));

  auto& r = p.result;
  r.scenario_name = sc.name;
  r.scenario_file = c.scenario.empty() ? sc.file : fs::absolute(c.scenario).string();
  r.base_variant = base;
  r.axes = axes;
  r.combinations = rows.size();
  r.gates = sc.gates;
  if (!c.pareto.empty()) {
    const std::size_t comma = c.pareto.find(',');
    if (comma == std::string::npos || c.pareto.find(',', comma + 1) != std::string::npos)
      throw InputError(
          kCommandLine, "--pareto",
          fmt::format("expected two metrics X,Y such as print_time_s,interfaces.too_cold_fraction, "
                      "got '{}'",
                      c.pareto));
    r.pareto = {scenarios::parse_objective(c.pareto.substr(0, comma), "--pareto"),
                scenarios::parse_objective(c.pareto.substr(comma + 1), "--pareto")};
  }
  r.sort = !c.sort.empty() ? scenarios::parse_objective(c.sort, "--sort")
           : r.pareto      ? r.pareto->first
                           : scenarios::Objective{"print_time_s", false};

  p.points = scenarios::expand_sweep(axes, rows);
  if (std::any_of(sc.gates.begin(), sc.gates.end(), [](const scenarios::Gate& g) { return g.relative; }))
    p.points.insert(p.points.begin(), SweepPoint{"baseline", {}});

  fs::path self = fs::read_symlink("/proc/self/exe");
  p.spec.command = {self.string(), "run"};
  if (!c.scenario.empty()) p.spec.command.push_back(fs::absolute(c.scenario).string());
  p.spec.command.insert(p.spec.command.end(), {"--variant", base, "-q"});
  for (const std::string& f : c.gate_files)
    p.spec.command.insert(p.spec.command.end(), {"--gates", fs::absolute(f).string()});
  for (const std::string& e : c.gate_exprs) p.spec.command.insert(p.spec.command.end(), {"--gate", e});
  p.spec.out_dir = fs::absolute(c.out_dir);
  p.spec.share_memory = !(variant->output.memory_budget_gb > 0);
  p.key = plan_key(c.scenario.empty() ? std::string("<built-in default>") : read_whole(c.scenario), base,
                   scenarios::contents_digest(inputs));
  return p;
}

// A variant's settings as one text, whatever their order: what matches a point with an earlier record.
std::string signature(const std::vector<Setting>& settings) {
  std::vector<std::string> parts;
  for (const Setting& s : settings) parts.push_back(s.key + "=" + s.value);
  std::sort(parts.begin(), parts.end());
  return fmt::format("{}", fmt::join(parts, "\n"));
}

void save_record(const RunSpec& spec, const SweepRecord& r);

// The records an earlier run of the same plan left in the output folder, for the points with the same
// settings that ran to the end; the others run (again). An earlier variant whose point has another name now
// (a value added to an axis renumbers the grid) has its folder moved to the new name first.
std::map<std::string, SweepRecord> resumable(const Plan& p) {
  std::map<std::string, SweepRecord> out;
  std::ifstream f(p.spec.out_dir / "sweep-plan.json");
  if (!f) return out;
  try {
    if (json::parse(f).at("key").get<std::string>() != p.key) return out;
  } catch (const json::exception&) {
    return out;
  }
  const fs::path variants = p.spec.out_dir / "variants";
  std::map<std::string, std::pair<std::string, SweepRecord>> earlier;  // signature -> (folder, record)
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(variants, ec)) {
    const std::string folder = e.path().filename().string();
    if (folder.starts_with(".") || !fs::exists(e.path() / "report.json")) continue;
    try {
      SweepRecord r = scenarios::parse_sweep_record(read_whole(e.path() / "sweep.json"), folder);
      std::string key = signature(r.settings);  // before r is moved into the map
      if (r.ran()) earlier.emplace(std::move(key), std::make_pair(folder, std::move(r)));
    } catch (const InputError&) {
      // Not a record (cut short, edited): that variant runs again.
    }
  }
  // Folders to move: first each aside, then each to its new name, so that two variants trading names (or a
  // chain of them) never meet.
  std::vector<std::pair<std::string, std::string>> moves;  // old folder -> new name
  for (const SweepPoint& point : p.points) {
    auto it = earlier.find(signature(point.settings));
    if (it == earlier.end()) continue;
    if (it->second.first != point.name) moves.emplace_back(it->second.first, point.name);
    SweepRecord r = std::move(it->second.second);
    r.name = point.name;
    r.settings = point.settings;
    out.emplace(point.name, std::move(r));
    earlier.erase(it);
  }
  for (const auto& [from, to] : moves) fs::rename(variants / from, variants / (".moving-" + from));
  for (const auto& [from, to] : moves) {
    fs::remove_all(variants / to);  // an earlier variant no point of this sweep has
    fs::rename(variants / (".moving-" + from), variants / to);
  }
  for (const auto& [name, r] : out) save_record(p.spec, r);
  return out;
}

void save_record(const RunSpec& spec, const SweepRecord& r) {
  write_file_atomic(variant_dir(spec, r.name) / "sweep.json", scenarios::sweep_record_json(r) + "\n");
}

std::string settings_text(const std::vector<Setting>& settings) {
  std::string s;
  for (const Setting& x : settings) s += (s.empty() ? "" : ", ") + x.key + "=" + x.value;
  return s.empty() ? "as the scenario has it" : s;
}

// Collects records as they come in: saves each, and says so.
class Gatherer {
 public:
  Gatherer(const Plan& p, bool quiet) : plan_(p), quiet_(quiet) {}
  void add(std::size_t index, SweepRecord r) {
    save_record(plan_.spec, r);
    ++done_;
    if (!quiet_)
      std::fprintf(stderr, "[%zu/%zu] %s %s in %.1f s (%s): %s\n", done_, todo_, r.name.c_str(),
                   r.ran() ? "ran" : "FAILED", r.wall_time_s, r.worker.c_str(),
                   settings_text(r.settings).c_str());
    records_[index] = std::move(r);
  }
  void set_todo(std::size_t n) { todo_ = n; }
  std::map<std::size_t, SweepRecord>& records() { return records_; }

 private:
  const Plan& plan_;
  bool quiet_;
  std::size_t done_ = 0, todo_ = 0;
  std::map<std::size_t, SweepRecord> records_;
};

// Runs `todo` (indices into the points) on this machine, up to `jobs` at once.
void run_local(const Plan& p, const std::vector<std::size_t>& todo, int jobs, int threads, Gatherer& g) {
  std::map<pid_t, std::pair<std::size_t, Launched>> running;
  std::size_t next = 0;
  while (next < todo.size() || !running.empty()) {
    while (static_cast<int>(running.size()) < jobs && next < todo.size()) {
      const std::size_t i = todo[next++];
      try {
        const Launched l = launch(p.spec, p.points[i], threads, jobs);
        running.emplace(l.pid, std::make_pair(i, l));
      } catch (const std::exception& e) {
        g.add(i, not_started(p.points[i], e.what(), "local"));
      }
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw InternalError(fmt::format("waiting for the variants: {}", std::strerror(errno)));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const auto [i, l] = it->second;
    running.erase(it);
    g.add(i, finish(p.spec, p.points[i], l, status, "local"));
  }
}

int cores() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// The report, once every point has its record.
int report(Plan& p, Gatherer& g, const std::map<std::string, SweepRecord>& resumed, Clock::time_point t0,
           bool quiet) {
  auto& result = p.result;
  for (std::size_t i = 0; i < p.points.size(); ++i) {
    if (const auto it = resumed.find(p.points[i].name); it != resumed.end()) {
      result.records.push_back(it->second);
    } else if (const auto r = g.records().find(i); r != g.records().end()) {
      result.records.push_back(r->second);
    } else {
      throw InternalError("variant " + p.points[i].name + " has no record");
    }
  }
  result.resumed = resumed.size();
  scenarios::apply_sweep_gates(result.records, result.gates);
  result.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  scenarios::write_sweep_reports(result, p.spec.out_dir);
  std::size_t failed = 0, gated = 0;
  for (const SweepRecord& r : result.records) {
    failed += r.ran() ? 0 : 1;
    gated += r.status == scenarios::SweepStatus::kGateFailed ? 1 : 0;
  }
  if (!quiet && (failed || gated))
    std::fprintf(stderr, "%zu variant(s) failed a gate, %zu did not run to the end\n", gated, failed);
  std::printf("%s: %zu variants in %.1f s (%s)\n", result.passed() ? "PASSED" : "FAILED",
              result.records.size(), result.wall_time_s, result.engine.c_str());
  std::printf("report: %s\n", (p.spec.out_dir / "sweep.html").c_str());
  return result.passed() ? 0 : 1;
}

// Prepares the output folder and works out what is left to run.
std::vector<std::size_t> prepare(const Plan& p, const std::map<std::string, SweepRecord>& resumed) {
  prepare_output_dir(p.spec.out_dir, "--out");
  write_file_atomic(p.spec.out_dir / "sweep-plan.json",
                    json({{"key", p.key}, {"run", spec_json(p.spec)}}).dump(2) + "\n");
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < p.points.size(); ++i)
    if (!resumed.count(p.points[i].name)) todo.push_back(i);
  return todo;
}

int run_plain(const SweepCommand& c) {
  const auto t0 = Clock::now();
  Plan p = make_plan(c);
  const auto resumed = resumable(p);
  const std::vector<std::size_t> todo = prepare(p, resumed);
  const int jobs =
      std::clamp(c.jobs > 0 ? c.jobs : 1, 1, static_cast<int>(std::max<std::size_t>(todo.size(), 1)));
  const int threads = c.threads > 0 ? c.threads : std::max(1, cores() / jobs);
  p.result.engine = todo.empty() ? std::string("nothing left to run: every variant from an earlier run")
                                 : fmt::format("{} local process{} of {} thread{}", jobs,
                                               jobs == 1 ? "" : "es", threads, threads == 1 ? "" : "s");
  if (!c.quiet)
    std::fprintf(stderr, "beadtwin %s: sweep of %s, %zu variants (%zu from an earlier run), %s\n",
                 BEADTWIN_VERSION, p.result.scenario_name.c_str(), p.points.size(), resumed.size(),
                 p.result.engine.c_str());
  Gatherer g(p, c.quiet);
  g.set_todo(todo.size());
  run_local(p, todo, jobs, threads, g);
  return report(p, g, resumed, t0, c.quiet);
}

#ifdef BEADTWIN_MPI_MODULE

// Lets the variants this rank starts use every core of the node. mpirun binds each rank to one core by
// default when it starts two ranks or fewer (Open MPI's --bind-to core), and a rank's children inherit its
// binding: a variant given two threads would run them both on one core, at about one and a half times the
// time (docs/PERFORMANCE.md). The variants take their share of the node by their thread count instead.
void unbind_from_cores(int threads) {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof mask, &mask) != 0 || CPU_COUNT(&mask) >= threads) return;
  CPU_ZERO(&mask);
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  for (long cpu = 0; cpu < online && cpu < CPU_SETSIZE; ++cpu) CPU_SET(static_cast<int>(cpu), &mask);
  (void)sched_setaffinity(0, sizeof mask,
                          &mask);  // not allowed (a cgroup's cpuset): the run is slower, no worse
}

// The sweep as one rank of an MPI job: the module runs the messages, these callbacks the work.
int run_mpi(const SweepCommand& c) {
  const auto t0 = Clock::now();
  std::optional<Plan> plan;  // rank 0's
  std::map<std::string, SweepRecord> resumed;
  std::vector<std::size_t> todo;
  std::optional<Gatherer> gatherer;
  mpi::Callbacks cb;
  cb.plan = [&](int ranks) {
    plan.emplace(make_plan(c));
    resumed = resumable(*plan);
    todo = prepare(*plan, resumed);
    plan->result.engine = fmt::format("MPI, {} ranks: rank 0 hands out the variants to {}", ranks, ranks - 1);
    if (!c.quiet)
      std::fprintf(stderr, "beadtwin %s: sweep of %s, %zu variants (%zu from an earlier run), %s\n",
                   BEADTWIN_VERSION, plan->result.scenario_name.c_str(), plan->points.size(), resumed.size(),
                   plan->result.engine.c_str());
    gatherer.emplace(*plan, c.quiet);
    gatherer->set_todo(todo.size());
    std::vector<std::string> items;
    for (const std::size_t i : todo) {
      const SweepPoint& point = plan->points[i];
      json settings = json::array();
      for (const Setting& s : point.settings) settings.push_back({s.key, s.value});
      items.push_back(
          json({{"name", point.name}, {"settings", settings}, {"spec", spec_json(plan->spec)}}).dump());
    }
    return items;
  };
  cb.gathered = [&](std::size_t item, const std::string& result, int rank) {
    gatherer->add(todo.at(item), scenarios::parse_sweep_record(result, fmt::format("rank {}", rank)));
  };
  cb.report = [&] { return report(*plan, *gatherer, resumed, t0, c.quiet); };
  cb.run = [&](const std::string& item, int sharing, const std::string& worker) {
    const json work = json::parse(item);
    SweepPoint point{work.at("name").get<std::string>(), {}};
    for (const json& s : work.at("settings"))
      point.settings.push_back({s.at(0).get<std::string>(), s.at(1).get<std::string>()});
    const int threads = c.threads > 0 ? c.threads : std::max(1, cores() / sharing);
    unbind_from_cores(threads);
    return scenarios::sweep_record_json(run_point(spec_of(work.at("spec")), point, threads, sharing, worker));
  };
  cb.plain = [&] {  // mpirun -n 1 binds its one rank to one core: the variants would all run on it
    unbind_from_cores(c.threads > 0 ? c.threads : cores());
    return run_plain(c);
  };
  return reinterpret_cast<mpi::Entry>(mpi_module_entry(mpi::kEntryName))(cb);
}

#endif

}  // namespace

int run_sweep(const SweepCommand& command) {
  if (launched_by_mpi()) {
#ifdef BEADTWIN_MPI_MODULE
    return run_mpi(command);
#else
    // Each rank would run the whole sweep into the same folder.
    throw InputError(kCommandLine, "mpirun",
                     "this beadtwin was built without MPI, so it cannot share a sweep among ranks: run the "
                     "sweep without mpirun, or build beadtwin where MPI is installed (tools/setup.sh does)");
#endif
  }
  return run_plain(command);
}

}  // namespace beadtwin::tools
