#include "thermal/heat.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <span>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/percentile.hpp"
#include "thermal/births.hpp"
#include "thermal/cvode.hpp"
#include "thermal/healing.hpp"
#include "thermal/history.hpp"
#include "thermal/interface_index.hpp"
#include "thermal/lumper.hpp"
#include "thermal/part_model.hpp"
#include "thermal/support.hpp"
#include "thermal/view_factor.hpp"

namespace beadtwin::thermal {
namespace {

// `material` with the deposition temperature of the hottest bead (ThermalCell::deposition_offset_k): the
// support's tables reach that far.
Material hottest_birth(const Material& material, const ThermalMesh& mesh) {
  Material m = material;
  double offset = 0.0;
  for (const ThermalCell& c : mesh.cells) offset = std::max(offset, c.deposition_offset_k);
  m.deposition_temp_c += offset;
  return m;
}

// The median of value(i) over cells [0, n), n > 0.
template <class F>
double median_over_cells(std::size_t n, const F& value) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = value(i);
  return median(std::move(v));
}

// Each bead's slices through its height (SupportCell::bead_top), top first: its column.
std::vector<std::vector<std::uint32_t>> bead_columns(std::span<const SupportCell> support) {
  std::vector<std::vector<std::uint32_t>> columns;
  for (std::uint32_t top = 0; top < support.size(); ++top) {
    if (support[top].bead_top != top) continue;
    std::vector<std::uint32_t>& column = columns.emplace_back();
    for (std::uint32_t c = top; c != SupportCell::kNone && support[c].bead_top == top; c = support[c].below)
      column.push_back(c);
  }
  return columns;
}

// By cell, the bead whose slice it is (SupportCell::bead_top: LumpRules::column); empty where every bead is
// one cell through.
std::vector<std::uint32_t> bead_column_of_cells(std::span<const SupportCell> support) {
  std::vector<std::uint32_t> column(support.size());
  bool sliced = false;
  for (std::size_t c = 0; c < support.size(); ++c) {
    column[c] = support[c].bead_top;
    sliced = sliced || column[c] != c;
  }
  if (!sliced) column.clear();
  return column;
}

// The cells' median conduction time constant, s (5 s when it is not finite: cells without contacts): it
// sets the longest step.
double median_time_constant_s(const PartModel& model) {
  const double tau =
      median_over_cells(model.size_of_model(), [&](std::size_t i) { return model.time_constant_s(i); });
  return std::isfinite(tau) ? tau : 5.0;
}

// What the births and the lumper take from the beads, each bead's slices through its height together.
struct Beads {
  // The median conduction time constant, s (as median_time_constant_s): it sets the birth interval, the
  // same on any number of cells through a bead. Thinner slices have shorter time constants, but only the
  // young ones keep them (the lumper merges a bead's slices once it is covered), and what they add to the
  // temperatures between births of this interval is within the solve's convergence (docs/validation.md,
  // mesh convergence).
  double median_time_constant_s = 5.0;
  double median_mass_kg = 0.0;
  int most_slices = 1;  // through one bead, at most 15
};

Beads beads_of(const PartModel& model, std::span<const SupportCell> support) {
  const std::vector<std::vector<std::uint32_t>> columns = bead_columns(support);
  Beads b;
  const double tau =
      median_over_cells(columns.size(), [&](std::size_t i) { return model.time_constant_s(columns[i]); });
  b.median_time_constant_s = std::isfinite(tau) ? tau : 5.0;
  b.median_mass_kg = median_over_cells(columns.size(), [&](std::size_t i) {
    double kg = 0.0;
    for (const std::uint32_t c : columns[i]) kg += model.mass_kg(c);
    return kg;
  });
  std::size_t most = 1;
  for (const std::vector<std::uint32_t>& column : columns) most = std::max(most, column.size());
  b.most_slices = static_cast<int>(std::min<std::size_t>(most, 15));
  return b;
}

// Across ranks, every rank must solve the same part and options, or their messages would not match: each
// compares a fingerprint of what it was given (FNV-1a over the cells' births, volumes and the links, and the
// options the integration depends on) with rank 0's.
void check_same_on_every_rank(const ThermalMesh& mesh, const HeatOptions& o, Communicator& ranks) {
  Fnv1a h;
  const auto mix = [&h](const auto& value) { h.add_value(value); };
  mix(mesh.cells.size());
  mix(mesh.links.size());
  for (const ThermalCell& c : mesh.cells) mix(c.birth_s), mix(c.volume_mm3), mix(c.open_area_mm2);
  for (const ThermalLink& l : mesh.links) mix(l.a), mix(l.b), mix(l.interface);
  mix(o.rel_tol), mix(o.abs_tol_k), mix(o.birth_interval_s), mix(o.cooldown_s), mix(o.max_cooldown_s);
  mix(o.lump), mix(o.view_factors);
  const double mine = static_cast<double>(h.value() >> 12);  // 52 bits: exact in a double
  if (ranks.gather_each(mine)[0] != mine)
    throw InternalError(
        fmt::format("thermal solve across ranks: rank {} was given another part than rank 0", ranks.rank()));
}

void check_options(const HeatOptions& o) {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(o.rel_tol))
    throw InputError({}, "thermal.rel_tol", fmt::format("must be > 0, got {}", o.rel_tol));
  if (!positive(o.abs_tol_k))
    throw InputError({}, "thermal.abs_tol", fmt::format("must be > 0, got {}", o.abs_tol_k));
  if (!(o.birth_interval_s >= 0.0) || !std::isfinite(o.birth_interval_s))
    throw InputError({}, "thermal.birth_interval",
                     fmt::format("must be 0 or more, got {}", o.birth_interval_s));
  if (!(o.cooldown_s >= 0.0) || !std::isfinite(o.cooldown_s))
    throw InputError({}, "thermal.cooldown", fmt::format("must be 0 or more, got {}", o.cooldown_s));
  if (!(o.max_cooldown_s >= 0.0) || !std::isfinite(o.max_cooldown_s))
    throw InputError({}, "thermal.max_cooldown", fmt::format("must be 0 or more, got {}", o.max_cooldown_s));
  if (!positive(o.sample_interval_s))
    throw InputError({}, "thermal.sample_interval", fmt::format("must be > 0, got {}", o.sample_interval_s));
  if (o.lump_depth < 1 || o.lump_depth > 100)
    throw InputError({}, "thermal.lump_depth", fmt::format("must be 1..100, got {}", o.lump_depth));
  if (o.lump_slice_beads < 1 || o.lump_slice_beads > 8)
    throw InputError({}, "thermal.lump_slice_beads", fmt::format("must be 1..8, got {}", o.lump_slice_beads));
  if (!(o.lump_tolerance_k >= 0.0) || !std::isfinite(o.lump_tolerance_k))
    throw InputError({}, "thermal.lump_tolerance",
                     fmt::format("must be 0 or more, got {}", o.lump_tolerance_k));
  for (std::size_t k = 0; k < o.fan.size(); ++k)
    if (!(o.fan[k].output >= 0.0 && o.fan[k].output <= 1.0) || !std::isfinite(o.fan[k].time_s) ||
        (k > 0 && o.fan[k].time_s < o.fan[k - 1].time_s))
      throw InputError({}, "fan",
                       fmt::format("setting {}: outputs must lie in 0..1 and times increase, got {} at {} s",
                                   k, o.fan[k].output, o.fan[k].time_s));
  if (o.krylov_dimension < 1 || o.krylov_dimension > 200)
    throw InputError({}, "thermal.krylov_dimension",
                     fmt::format("must be 1..200, got {}", o.krylov_dimension));
}

// One heat solve (solve_heat): the part's model, its birth schedule and interfaces, and the integrator
// stepping from birth group to birth group and through the cooldown, with the healing integrator, the
// history recorder and the lumper looking at every step or group, then on while interfaces still heal.
//
// The model's cells are the mesh's cells until some are lumped, after which model_of_[i] is mesh cell i's
// model cell (non-decreasing; model_of_[n] is the model's cell count). Everything read per step is kept by
// model cell and indexed anew at each lumping.
class HeatSolve {
 public:
  HeatSolve(const ThermalMesh& mesh, std::size_t layer_count, double end_s, const Material& material,
            const Environment& env, const HeatOptions& options);
  HeatResult run();

 private:
  // Births the cells of group `g` in `state` (the first cap_ model cells and the energy lost): the
  // interfaces they open take their substrate's temperature and cooling rate.
  void born_group(const BirthGroup& g, std::span<double> state);
  // Whether the soft material under interface r's younger cell carries it (r.on_top), from `state`.
  void judge_support(InterfaceResult& r, std::span<const double> state) const;
  // The substrate's temperature, rate and surface temperature for an interface whose older cell is born.
  void measure_substrate(InterfaceResult& r, std::span<const double> state) const;
  // The view factors of the cells whose view the births so far changed, into the model.
  void update_views();
  // Lumps the settled cells in before_ (HeatOptions::lump) if it is time; true if any were.
  bool lump_settled();
  // Makes room in the integrator's state for the model cells below `end`: by half at least, so the
  // integrator is rebuilt a few dozen times in all.
  void grow_state(std::size_t end);
  // A new integrator on the model as it is now (after growing or lumping), its work so far counted.
  void restart_integrator();
  // The fan's output at time t (HeatOptions::fan): the last setting at or before it, 0 before any.
  double fan_at(double t) const {
    const auto after = std::upper_bound(options_.fan.begin(), options_.fan.end(), t,
                                        [](double time, const FanSetting& f) { return time < f.time_s; });
    return after == options_.fan.begin() ? 0.0 : std::prev(after)->output;
  }
  // Integrates to `target`: the healing over each step, and the history in it.
  void advance(double target);
  // One integrator step towards `target`: the healing over it, and the history in it if `record`.
  void step(double target, bool record);
  // After the cooldown: steps on while an interface is at or above the healing threshold, up to t_cap_.
  void heal_until_cold();
  void finish();

  const ThermalMesh& mesh_;
  const Material& material_;
  const HeatOptions& options_;
  std::size_t n_;  // mesh cells
  Support support_;
  // The mesh's support cells, or for a mesh built without them (by hand) those measured from it alone.
  std::vector<SupportCell> own_support_;
  std::span<const SupportCell> support_cells_;
  PartModel model_;
  double median_tau_;
  Beads beads_;
  BirthSchedule births_;
  // First birth, end of the print (the last birth or end_s), end of the cooldown, latest end of the healing.
  double t0_, t_print_, t_end_, t_cap_;
  std::vector<InterfaceResult> interfaces_;
  InterfaceIndex index_;
  HealingIntegrator healing_;
  HistoryRecorder history_;
  Lumper lumper_;
  // By model cell, the bead whose slices through its height it holds (LumpRules::column); empty where every
  // bead is one cell through.
  std::vector<std::uint32_t> column_;
  std::vector<std::uint32_t> model_of_;
  std::unique_ptr<SkyView> sky_;  // null without view factors
  std::vector<CellView> views_;   // per mesh cell, as the model has them
  std::size_t mesh_born_ = 0;     // mesh cells born so far: [0, mesh_born_)
  // The integrator's state (PartModel::set_capacity) at the end of the last step; and every model cell's
  // temperature for the cells beyond it (unborn: they wait at the deposition temperature).
  std::vector<double> temps_, before_;
  std::vector<double> cooled_;  // before_ at the end of the cooldown
  std::size_t cap_ = 0;
  CvodeOptions cvode_options_;
  std::unique_ptr<Cvode> cvode_;
  double t_ = 0.0;
  long steps_ = 0, rhs_ = 0, linear_ = 0;      // of the integrators replaced
  std::vector<double> now_all_, between_all_;  // across ranks: the whole state gathered
  std::vector<double> first_point_;            // the state at the first Gauss-Legendre point of a step
  HeatResult result_;
};

HeatSolve::HeatSolve(const ThermalMesh& mesh, std::size_t layer_count, double end_s, const Material& material,
                     const Environment& env, const HeatOptions& options)
    : mesh_(mesh),
      material_(material),
      options_(options),
      n_(mesh.cells.size()),
      support_(hottest_birth(material, mesh), options.support),
      own_support_(mesh.support.size() == mesh.cells.size() ? std::vector<SupportCell>{}
                                                            : support_cells(mesh, nullptr)),
      support_cells_(own_support_.empty() ? std::span<const SupportCell>(mesh.support) : own_support_),
      model_(mesh, material, env),
      median_tau_(median_time_constant_s(model_)),
      beads_(beads_of(model_, support_cells_)),
      births_(plan_births(mesh.cells, beads_.median_time_constant_s, options)),
      t0_(births_.groups.front().time_s),
      t_print_(std::max(births_.groups.back().time_s, end_s)),
      t_end_(t_print_ + options.cooldown_s),
      t_cap_(t_print_ + std::max(options.cooldown_s, options.max_cooldown_s)),
      interfaces_(list_interfaces(mesh)),
      index_(interfaces_, n_),
      healing_(material, index_, options.healing_laws),
      history_(mesh, layer_count, t0_, t_end_, options),
      lumper_(options, beads_.median_mass_kg, beads_.most_slices),
      column_(bead_column_of_cells(support_cells_)),
      model_of_(n_ + 1) {
  model_.set_tolerances(options.rel_tol, options.abs_tol_k);
  model_.set_communicator(options.communicator);
  std::iota(model_of_.begin(), model_of_.end(), 0u);
  history_.index(model_of_);
  result_.automatic_interval_s = births_.automatic_interval_s;
  result_.birth_interval_s = births_.interval_s;
  if (!births_.note.empty()) result_.notes.push_back(births_.note);
  result_.birth_events = births_.groups.size();
  result_.start_time_s = t0_;
  result_.end_time_s = t_end_;

  temps_.assign(n_, material.deposition_temp_c);
  cap_ = std::min(n_, std::max<std::size_t>(births_.groups.front().end, 1024));
  before_.assign(temps_.begin(), temps_.begin() + static_cast<std::ptrdiff_t>(cap_));
  before_.push_back(0.0);  // energy lost
  if (options.view_factors && mesh.cell_grid) {
    sky_ = std::make_unique<SkyView>(mesh);
    views_.resize(n_);
  }
  born_group(births_.groups.front(), before_);
  update_views();
  model_.set_fan(fan_at(t0_));
  model_.set_capacity(cap_);
  cvode_options_.solver = LinearSolver::kGmres;
  cvode_options_.krylov_dimension = options.krylov_dimension;
  // No step longer than a few cell time constants. GMRES with a diagonal preconditioner carries a
  // correction a few cells per iteration; over a step of many time constants (a long pause, the cooldown
  // towards steady state) a temperature depends on cells far away, GMRES stops short of it, and the Newton
  // test, which sees only small corrections, passes a state kelvins off. A steady bar of 50 cells ends
  // 1e-3 of its temperature drop off its own network with no limit, 2e-5 with this one (heat_test).
  cvode_options_.max_step_s = 4.0 * median_tau_;
  cvode_options_.communicator = model_.communicator();
  cvode_ = std::make_unique<Cvode>(model_, t0_, model_.local(before_), cvode_options_);
  t_ = t0_;
}

HeatResult HeatSolve::run() {
  const std::vector<BirthGroup>& groups = births_.groups;
  for (std::size_t g = 1; g < groups.size(); ++g) {
    advance(groups[g].time_s);
    const bool lumped = options_.lump && lump_settled();
    const bool grow = model_of_[groups[g].end] > cap_;
    if (grow) grow_state(groups[g].end);
    born_group(groups[g], before_);
    update_views();
    model_.set_fan(fan_at(t_));
    if (grow || lumped) restart_integrator();
    // The first step tries to reach the next group at once: the temperatures move slowly against the birth
    // interval (it is a fifth of a cell's time constant), so CVODE usually takes it.
    const double interval = births_.interval_s;
    const double gap = g + 1 < groups.size() ? groups[g + 1].time_s - t_ : interval;
    cvode_->reinit(t_, model_.local(before_), std::max(gap, 1e-3 * interval));
    if (options_.progress) options_.progress((t_ - t0_) / std::max(t_end_ - t0_, 1e-9));
  }
  // The fan's changes after the last birth (switched off at the end of the program, say), as they come.
  for (const FanSetting& f : options_.fan) {
    if (f.time_s <= t_ || f.time_s >= t_end_) continue;
    advance(f.time_s);
    model_.set_fan(f.output);
    cvode_->reinit(t_, model_.local(before_), 1e-3 * births_.interval_s);
  }
  advance(t_end_);
  cooled_ = before_;
  heal_until_cold();
  if (options_.progress) options_.progress(1.0);
  healing_.flush_lumps(index_);
  finish();
  return std::move(result_);
}

void HeatSolve::judge_support(InterfaceResult& r, std::span<const double> state) const {
  const auto temp_c = [&](std::uint32_t c) {
    return c < mesh_born_ ? state[model_of_[c]] : model_.birth_c(model_of_[c]);
  };
  r.support = support_.judge(support_cells_, r.older, r.younger, births_.interval_s, temp_c, r.substrate_c);
}

void HeatSolve::measure_substrate(InterfaceResult& r, std::span<const double> state) const {
  // The older cell's bead through its height, by volume: the same on any number of cells through it.
  const std::uint32_t top = support_cells_[r.older].bead_top;
  double volume = 0.0, temp = 0.0, rate = 0.0, loss = 0.0;
  for (std::uint32_t c = top; c != SupportCell::kNone && support_cells_[c].bead_top == top;
       c = support_cells_[c].below) {
    const double v = mesh_.cells[c].volume_mm3;
    volume += v;
    temp += v * state[model_of_[c]];
    rate += v * model_.rate(model_of_[c], state.data(), loss);
  }
  r.substrate_c = temp / volume;
  r.substrate_rate_K_s = rate / volume;
  const std::size_t older = model_of_[r.older];
  r.substrate_surface_c = model_.face_surface_c(older, model_of_[r.younger], state[older]);
}

void HeatSolve::born_group(const BirthGroup& g, std::span<double> state) {
  for (std::size_t i = mesh_born_; i < g.end; ++i)
    for (const std::uint32_t k : index_.of_younger(i)) {
      InterfaceResult& r = interfaces_[k];
      r.bead_c = model_.birth_c(model_of_[r.younger]);
      r.substrate_c = model_.birth_c(model_of_[r.older]);
      r.substrate_surface_c = r.substrate_c;
      if (r.older < mesh_born_) measure_substrate(r, state);
      if (r.on_top) judge_support(r, state);
    }
  model_.birth(model_of_[g.end], state);
  mesh_born_ = g.end;
}

void HeatSolve::update_views() {
  if (!sky_) return;
  for (const ViewChange& v : sky_->update(mesh_born_)) {
    const double area_m2 = mesh_.cells[v.cell].open_area_mm2 * 1e-6;
    CellView& had = views_[v.cell];
    model_.add_view(model_of_[v.cell], area_m2 * (v.view.sky - had.sky),
                    area_m2 * (v.view.table - had.table));
    had = v.view;
  }
}

bool HeatSolve::lump_settled() {
  const std::vector<std::uint32_t> to = lumper_.settled(model_, before_, mesh_born_, column_);
  if (to.empty()) return false;
  const std::size_t m = model_.size_of_model();
  const std::uint32_t runs = to.back() + 1;
  // The beads lumped from their slices conduct from their own centroids (PartModel::lump); a cell of more
  // than one bead holds none.
  std::vector<std::uint8_t> recentre;
  if (!column_.empty()) {
    std::vector<std::uint32_t> column(runs, kNoColumn);
    for (std::size_t k = 0; k < m; ++k)
      column[to[k]] = k == 0 || to[k] != to[k - 1] || column_[k] == column[to[k]] ? column_[k] : kNoColumn;
    column_ = std::move(column);
    recentre.resize(runs);
    for (std::size_t k = 1; k < m; ++k)  // of more than one cell
      if (to[k] == to[k - 1] && column_[to[k]] != kNoColumn) recentre[to[k]] = 1;
  }
  healing_.flush_lumps(index_);
  model_.lump(to, before_, recentre);
  for (std::uint32_t& c : model_of_) c = c < m ? to[c] : runs;
  temps_.assign(model_of_[n_], material_.deposition_temp_c);
  cap_ = model_.capacity();
  index_.index(model_of_);
  healing_.reset_lumps(index_);
  history_.index(model_of_);
  ++result_.lump_events;
  return true;
}

void HeatSolve::grow_state(std::size_t end) {
  const double lost = before_[cap_];
  std::copy(before_.begin(), before_.end() - 1, temps_.begin());
  cap_ = std::min<std::size_t>(model_of_[n_], std::max<std::size_t>(model_of_[end], cap_ + cap_ / 2));
  before_.assign(temps_.begin(), temps_.begin() + static_cast<std::ptrdiff_t>(cap_));
  before_.push_back(lost);
}

void HeatSolve::restart_integrator() {
  steps_ += cvode_->steps();
  rhs_ += cvode_->rhs_evaluations();
  linear_ += cvode_->linear_iterations();
  cvode_.reset();
  model_.set_capacity(cap_);
  cvode_ = std::make_unique<Cvode>(model_, t_, model_.local(before_), cvode_options_);
}

void HeatSolve::advance(double target) {
  if (target <= t_) return;
  cvode_->set_stop_time(target);
  while (t_ < target) step(target, true);
}

void HeatSolve::step(double target, bool record) {
  const auto state_at = [&](double t) { return model_.gather(cvode_->interpolate(t), between_all_); };
  const double t_prev = t_;
  t_ = cvode_->step(target);
  const double half = 0.5 * (t_ - t_prev);
  const double mid = t_prev + half;
  const double offset = half / std::sqrt(3.0);
  // Across ranks, every rank gathers the whole state: what follows is the same on all of them.
  const std::span<const double> now = model_.gather(cvode_->state(), now_all_);
  if (healing_.find(index_, model_.born(), before_, now)) {
    // Gauss-Legendre, two points: exact for cubics in t, as CVODE's interpolant is at low order.
    const std::span<const double> y0 = state_at(mid - offset);
    first_point_.assign(y0.begin(), y0.end());
    healing_.integrate(index_, half, first_point_, state_at(mid + offset));
  }
  std::copy(now.begin(), now.end(), before_.begin());
  if (record) history_.record_until(t_, now, mesh_born_, model_.born(), state_at);
}

void HeatSolve::heal_until_cold() {
  if (t_cap_ > t_) cvode_->set_stop_time(t_cap_);
  while (t_ < t_cap_ && healing_.any_warm(index_, before_)) step(t_cap_, false);
  result_.healing_end_s = t_;
}

void HeatSolve::finish() {
  const std::span<const double> integral = healing_.integrals();
  for (std::size_t k = 0; k < integral.size(); ++k) {
    interfaces_[k].healing_integral = integral[k];
    interfaces_[k].healing = std::min(1.0, std::pow(integral[k], 0.25));
  }
  for (std::size_t law = 1; law <= options_.healing_laws.size(); ++law) {
    const std::span<const double> i = healing_.integrals(law);
    result_.law_integrals.emplace_back(i.begin(), i.end());
  }
  for (std::uint32_t k = 0; k < interfaces_.size(); ++k) {
    InterfaceResult& r = interfaces_[k];
    r.verdict = judge_interface(r.on_top && r.support.too_hot(), r.healing, material_);
    r.verdict_cold = r.verdict_hot = r.verdict;
    r.still_warm = healing_.warm(index_, before_, k);
    result_.still_warm += r.still_warm;
    result_.still_warm_area_mm2 += r.still_warm ? r.area_mm2 : 0.0;
  }
  if (result_.still_warm > 0)
    result_.notes.push_back(fmt::format(
        "thermal: {} interfaces were still at or above the healing threshold ({:g} C) {:g} s after the last "
        "layer (thermal.max_cooldown); their healing is what it had reached by then",
        result_.still_warm, material_.healing_min_temp_c, t_cap_ - t_print_));
  result_.interfaces = std::move(interfaces_);
  history_.take(result_);

  std::copy(cooled_.begin(), cooled_.end() - 1, temps_.begin());
  result_.final_temp_c.resize(n_);
  for (std::size_t i = 0; i < n_; ++i) result_.final_temp_c[i] = static_cast<float>(temps_[model_of_[i]]);
  for (std::size_t c = 0; c < n_; ++c)  // mesh cells sharing their model cell
    result_.lumped_cells += (c > 0 && model_of_[c] == model_of_[c - 1]) || model_of_[c + 1] == model_of_[c];
  result_.model_cells = model_of_[n_];
  if (result_.lumped_cells > 0)
    result_.notes.push_back(fmt::format(
        "thermal: {} of {} cells lumped once settled ({} or more contacts below the top, within {:g} K of "
        "their neighbours along the bead), {} cells at the end; set thermal.lump: false to keep every cell",
        result_.lumped_cells, n_, options_.lump_depth + 1, options_.lump_tolerance_k, result_.model_cells));
  result_.energy_in_J = model_.energy_in_J();
  result_.energy_lost_J = cooled_[cap_];
  result_.energy_stored_J = model_.energy_stored_J(temps_);
  const double scale = std::max(std::abs(result_.energy_in_J),
                                std::abs(result_.energy_lost_J) + std::abs(result_.energy_stored_J));
  result_.energy_balance_rel_error =
      scale > 0.0 ? std::abs(result_.energy_in_J - result_.energy_lost_J - result_.energy_stored_J) / scale
                  : 0.0;
  if (sky_) {
    result_.view_updates = sky_->updates();
    result_.view_rays = sky_->rays_cast();
  }
  result_.ranks = model_.communicator() != nullptr ? model_.communicator()->size() : 1;
  result_.steps = steps_ + cvode_->steps();
  result_.rhs_evaluations = rhs_ + cvode_->rhs_evaluations();
  result_.linear_iterations = linear_ + cvode_->linear_iterations();
}

}  // namespace

std::vector<FanSetting> fan_schedule(const Toolpath& toolpath) {
  std::vector<FanSetting> out;
  float last = 0.0f;
  for (const Move& m : toolpath.moves) {
    if (m.fan == last) continue;
    out.push_back({.time_s = m.start_s, .output = m.fan});
    last = m.fan;
  }
  return out;
}

HeatResult solve_heat(const ThermalMesh& mesh, std::size_t layer_count, double end_s,
                      const Material& material, const Environment& env, const HeatOptions& options) {
  check_options(options);
  if (mesh.cells.empty()) return {};
  if (options.communicator != nullptr && options.communicator->size() > 1)
    check_same_on_every_rank(mesh, options, *options.communicator);
  HeatSolve solve(mesh, layer_count, end_s, material, env, options);
  return solve.run();
}

}  // namespace beadtwin::thermal
