#include "thermal/heat.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <span>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "thermal/cvode.hpp"
#include "thermal/for_range.hpp"
#include "thermal/part_model.hpp"

namespace beadtwin::thermal {
namespace {

// The median of value(i) over cells [0, n), n > 0.
template <class F>
double median_over_cells(std::size_t n, const F& value) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = value(i);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  return v[n / 2];
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
  mix(o.rel_tol), mix(o.abs_tol_k), mix(o.birth_interval_s), mix(o.cooldown_s), mix(o.lump);
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
  if (!positive(o.sample_interval_s))
    throw InputError({}, "thermal.sample_interval", fmt::format("must be > 0, got {}", o.sample_interval_s));
  if (o.lump_depth < 1 || o.lump_depth > 100)
    throw InputError({}, "thermal.lump_depth", fmt::format("must be 1..100, got {}", o.lump_depth));
  if (!(o.lump_tolerance_k >= 0.0) || !std::isfinite(o.lump_tolerance_k))
    throw InputError({}, "thermal.lump_tolerance",
                     fmt::format("must be 0 or more, got {}", o.lump_tolerance_k));
  if (o.krylov_dimension < 1 || o.krylov_dimension > 200)
    throw InputError({}, "thermal.krylov_dimension",
                     fmt::format("must be 1..200, got {}", o.krylov_dimension));
}

}  // namespace

HeatResult solve_heat(const ThermalMesh& mesh, std::size_t layer_count, double end_s,
                      const Material& material, const Environment& env, const HeatOptions& options) {
  check_options(options);
  HeatResult result;
  const std::size_t n = mesh.cells.size();
  if (n == 0) return result;
  if (options.communicator != nullptr && options.communicator->size() > 1)
    check_same_on_every_rank(mesh, options, *options.communicator);
  PartModel model(mesh, material, env);
  model.set_tolerances(options.rel_tol, options.abs_tol_k);
  model.set_communicator(options.communicator);

  // The cells' median conduction time constant sets the birth interval and the longest step.
  double median_tau = median_over_cells(n, [&](std::size_t i) { return model.time_constant_s(i); });
  if (!std::isfinite(median_tau)) median_tau = 5.0;
  // The birth interval and the groups of cells born together.
  result.automatic_interval_s = 0.2 * median_tau;
  double interval = options.birth_interval_s > 0.0 ? options.birth_interval_s : result.automatic_interval_s;
  if (options.birth_interval_s <= 0.0) {  // at most about max_automatic_birth_events: each group spans one
    const double span = mesh.cells.back().birth_s - mesh.cells.front().birth_s;
    interval = std::max(
        interval, span / static_cast<double>(std::max<std::size_t>(options.max_automatic_birth_events, 1)));
    if (interval > result.automatic_interval_s)
      result.notes.push_back(fmt::format(
          "thermal birth interval {:.3g} s instead of {:.3g} s (a fifth of the cells' median time constant), "
          "so that the print's cells are born in at most about {} events; set thermal.birth_interval to "
          "choose",
          interval, result.automatic_interval_s, options.max_automatic_birth_events));
  }
  result.birth_interval_s = interval;
  struct Group {
    std::size_t end = 0;  // cells [previous end, end)
    double time_s = 0.0;
  };
  std::vector<Group> groups;
  for (std::size_t i = 0; i < n;) {
    const double first = mesh.cells[i].birth_s;
    std::size_t j = i;
    while (j < n && mesh.cells[j].birth_s <= first + interval) ++j;
    groups.push_back({j, 0.5 * (first + mesh.cells[j - 1].birth_s)});
    i = j;
  }
  result.birth_events = groups.size();

  // Interfaces, by the younger cell (each group opens its own).
  std::vector<std::vector<std::size_t>> by_younger(n);
  for (std::size_t l = 0; l < mesh.links.size(); ++l) {
    const ThermalLink& link = mesh.links[l];
    if (!link.interface) continue;
    InterfaceResult r;
    r.older = link.a;
    r.younger = link.b;
    r.area_mm2 = link.area_mm2();
    const double length = link.area_vector_mm2.norm();
    r.on_top = length > 0.0 && std::abs(link.area_vector_mm2.z()) >= 0.5 * length;
    by_younger[link.b].push_back(result.interfaces.size());
    result.interfaces.push_back(r);
  }

  // The model's cells: the mesh's cells until some are lumped (settled cells, below), after which
  // model_of[i] is mesh cell i's model cell (non-decreasing; model_of[n] is the model's cell count).
  // Everything the integrator reads per step is kept by model cell and rebuilt at each lumping.
  std::vector<std::uint32_t> model_of(n + 1);
  for (std::size_t i = 0; i <= n; ++i) model_of[i] = static_cast<std::uint32_t>(i);
  std::size_t mesh_born = 0;  // mesh cells born so far: [0, mesh_born)

  // Interfaces by both model cells (the healing integral is advanced only where a cell is warm enough to
  // heal), flat, each entry with the interface's cells beside it: the scan for healing interfaces after every
  // step reads memory in order rather than chasing per-cell lists and interface records (that was most of its
  // time). An interface inside one lumped cell is not listed: its two sides are at the lumped cell's
  // temperature, so it heals at the lumped cell's rate, integrated once per lumped cell (lump_integral) and
  // handed to each of its inner interfaces when the cell is lumped again or at the end.
  struct CellInterface {
    std::uint32_t interface, other, younger;
  };
  std::vector<std::size_t> cell_first;
  std::vector<CellInterface> cell_interfaces;
  // Each interface's two model cells, packed: the healing rate reads them for every healing interface twice a
  // step, and from the interface records (64 bytes each) the default scenario's thermal stage took 0.3 s
  // longer.
  std::vector<std::array<std::uint32_t, 2>> cells_of(result.interfaces.size());
  std::vector<std::size_t> inner_first;  // model cell g's inner interfaces: [inner_first[g], [g + 1])
  std::vector<std::uint32_t> inner;      // interfaces
  std::vector<double> lump_integral;     // per model cell: ∫ dt / t_w at its temperature since lumped
  std::vector<double> integral(result.interfaces.size(), 0.0);  // ∫ dt / t_w so far
  // The layers' share of each model cell, for the history: (layer, volume), by model cell.
  std::vector<std::size_t> part_first;
  std::vector<std::pair<std::uint32_t, double>> parts;
  const auto index_model = [&] {
    const std::size_t m = model_of[n];
    cell_first.assign(m + 1, 0);
    inner_first.assign(m + 1, 0);
    for (std::size_t k = 0; k < result.interfaces.size(); ++k) {
      const std::uint32_t a = model_of[result.interfaces[k].older],
                          b = model_of[result.interfaces[k].younger];
      cells_of[k] = {a, b};
      if (a == b) {
        ++inner_first[a + 1];
      } else {
        ++cell_first[a + 1];
        ++cell_first[b + 1];
      }
    }
    for (std::size_t g = 0; g < m; ++g)
      cell_first[g + 1] += cell_first[g], inner_first[g + 1] += inner_first[g];
    cell_interfaces.resize(cell_first[m]);
    inner.resize(inner_first[m]);
    std::vector<std::size_t> next(cell_first.begin(), cell_first.end() - 1);
    std::vector<std::size_t> next_inner(inner_first.begin(), inner_first.end() - 1);
    for (std::uint32_t k = 0; k < result.interfaces.size(); ++k) {
      const auto [a, b] = cells_of[k];
      if (a == b) {
        inner[next_inner[a]++] = k;
        continue;
      }
      cell_interfaces[next[a]++] = {k, b, b};
      cell_interfaces[next[b]++] = {k, a, b};
    }
    lump_integral.assign(m, 0.0);
    part_first.assign(m + 1, 0);
    parts.clear();
    std::uint32_t last = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const int layer = mesh.cells[i].layer;
      if (layer < 0 || static_cast<std::size_t>(layer) >= layer_count) continue;
      const std::uint32_t g = model_of[i];
      // A model cell's mesh cells are consecutive: its entries of one layer (most have one) are merged.
      if (!parts.empty() && last == g && parts.back().first == static_cast<std::uint32_t>(layer)) {
        parts.back().second += mesh.cells[i].volume_mm3;
      } else {
        parts.emplace_back(static_cast<std::uint32_t>(layer), mesh.cells[i].volume_mm3);
        ++part_first[g + 1];
      }
      last = g;
    }
    for (std::size_t g = 0; g < m; ++g) part_first[g + 1] += part_first[g];
  };
  // Hands each lumped cell's healing to its inner interfaces.
  const auto flush_lumps = [&] {
    for (std::size_t g = 0; g + 1 < inner_first.size(); ++g)
      for (std::size_t e = inner_first[g]; e < inner_first[g + 1]; ++e)
        integral[inner[e]] += lump_integral[g];
    std::fill(lump_integral.begin(), lump_integral.end(), 0.0);
  };
  index_model();

  const Reptation reptation(material);
  // A cell is warm when it may be above the healing threshold during a step: at either end (with a margin
  // for what the interpolant does between them). An interface heals only while one of its cells is warm.
  const double warm_c = reptation.min_temp_c() - 1.0;
  std::vector<char> warm(n, 0);
  std::vector<std::uint32_t> healing_now, lumps_healing_now;

  // History samples.
  const double t0 = groups.front().time_s;
  const double t_end = std::max(groups.back().time_s, end_s) + options.cooldown_s;
  result.start_time_s = t0;
  result.end_time_s = t_end;
  result.layer_temp_c.assign(layer_count, {});
  double next_sample = t0;
  // (time, index of the request), in time order.
  std::vector<std::pair<double, std::size_t>> snapshot_times;
  for (std::size_t k = 0; k < options.snapshot_times_s.size(); ++k)
    snapshot_times.emplace_back(std::clamp(options.snapshot_times_s[k], t0, t_end), k);
  std::sort(snapshot_times.begin(), snapshot_times.end());
  std::size_t next_snapshot = 0;
  const auto snapshot = [&](double t, std::size_t request, std::span<const double> y) {
    TemperatureSnapshot s;
    s.time_s = t;
    s.request = request;
    s.temp_c.assign(n, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t i = 0; i < mesh_born; ++i) s.temp_c[i] = static_cast<float>(y[model_of[i]]);
    result.snapshots.push_back(std::move(s));
  };
  std::vector<double> layer_sum(layer_count), layer_volume(layer_count);
  const auto sample = [&](double t, std::span<const double> y) {
    std::fill(layer_sum.begin(), layer_sum.end(), 0.0);
    std::fill(layer_volume.begin(), layer_volume.end(), 0.0);
    for (std::size_t g = 0; g < model.born(); ++g)
      for (std::size_t e = part_first[g]; e < part_first[g + 1]; ++e) {
        layer_sum[parts[e].first] += parts[e].second * y[g];
        layer_volume[parts[e].first] += parts[e].second;
      }
    result.sample_times_s.push_back(t);
    for (std::size_t k = 0; k < layer_count; ++k)
      result.layer_temp_c[k].push_back(layer_volume[k] > 0.0
                                           ? static_cast<float>(layer_sum[k] / layer_volume[k])
                                           : std::numeric_limits<float>::quiet_NaN());
  };

  // The integrator's state (PartModel::set_capacity) at the end of the last step; and every model cell's
  // temperature for the cells beyond it (unborn: they wait at the deposition temperature).
  std::vector<double> temps(n, material.deposition_temp_c);
  std::size_t cap = std::min(n, std::max<std::size_t>(groups.front().end, 1024));
  std::vector<double> before(temps.begin(), temps.begin() + static_cast<std::ptrdiff_t>(cap));
  before.push_back(0.0);  // energy lost
  const auto born_group = [&](const Group& g, std::span<double> state) {
    for (std::size_t i = mesh_born; i < g.end; ++i)
      for (const std::size_t k : by_younger[i]) {
        InterfaceResult& r = result.interfaces[k];
        r.substrate_c = material.deposition_temp_c;
        if (r.older < mesh_born) {
          double loss = 0.0;
          r.substrate_c = state[model_of[r.older]];
          r.substrate_rate_K_s = model.rate(model_of[r.older], state.data(), loss);
        }
      }
    model.birth(model_of[g.end], state);
    mesh_born = g.end;
  };
  born_group(groups.front(), before);
  model.set_capacity(cap);

  // Settled cells (HeatOptions::lump): lumped where they are far enough below the top and even enough in
  // temperature that one temperature stands for the run. Checked when enough cells have been born since.
  const double median_mass = median_over_cells(n, [&](std::size_t i) { return model.mass_kg(i); });
  std::size_t born_at_check = 0;
  // Lumps the settled cells in `state` (the first `cap` model cells and the energy lost); true if any were.
  const auto lump_settled = [&](std::vector<double>& state) {
    const std::size_t born = model.born();
    if (mesh_born < born_at_check + std::max(options.lump_check_cells, born / 4)) return false;
    born_at_check = mesh_born;
    // Distance in contacts from the top (cells with a neighbour not yet born), up to lump_depth.
    constexpr std::uint8_t kFar = 255;
    std::vector<std::uint8_t> depth(born, kFar);
    std::vector<std::uint32_t> front, next_front;
    for (std::size_t i = 0; i < born; ++i)
      if (model.on_top(i)) depth[i] = 0, front.push_back(static_cast<std::uint32_t>(i));
    for (int d = 1; d <= options.lump_depth && !front.empty(); ++d) {
      next_front.clear();
      for (const std::uint32_t i : front)
        for (const std::uint32_t j : model.neighbours(i))
          if (j < born && depth[j] == kFar) depth[j] = static_cast<std::uint8_t>(d), next_front.push_back(j);
      std::swap(front, next_front);
    }
    // Runs of consecutive settled cells, each touching the run before it, within lump_tolerance_k of one
    // another and of at most lump_max_cells median cells' mass.
    const std::size_t m = model.size_of_model();
    std::vector<std::uint32_t> to(m);
    std::uint32_t g = 0;
    std::size_t i = 0;
    while (i < m) {
      std::size_t j = i + 1;
      if (i < born && depth[i] == kFar) {
        double lo = state[i], hi = state[i], mass = model.mass_kg(i);
        for (; j < born && depth[j] == kFar; ++j) {
          const double t = state[j];
          if (std::max(hi, t) - std::min(lo, t) > options.lump_tolerance_k) break;
          if (mass + model.mass_kg(j) > options.lump_max_cells * median_mass) break;
          const auto nb = model.neighbours(j);
          const auto it = std::lower_bound(nb.begin(), nb.end(), static_cast<std::uint32_t>(i));
          if (it == nb.end() || *it >= j) break;  // does not touch the run
          lo = std::min(lo, t), hi = std::max(hi, t), mass += model.mass_kg(j);
        }
      }
      for (std::size_t k = i; k < j; ++k) to[k] = g;
      ++g;
      i = j;
    }
    if (m - g < std::max<std::size_t>(64, born / 16)) return false;  // too few to be worth a restart
    flush_lumps();
    model.lump(to, state);
    for (std::uint32_t& c : model_of) c = c < m ? to[c] : g;
    temps.assign(model_of[n], material.deposition_temp_c);
    warm.assign(model_of[n], 0);
    cap = model.capacity();
    index_model();
    ++result.lump_events;
    return true;
  };

  CvodeOptions co;
  co.solver = LinearSolver::kGmres;
  co.krylov_dimension = options.krylov_dimension;
  // No step longer than a few cell time constants. GMRES with a diagonal preconditioner carries a
  // correction a few cells per iteration; over a step of many time constants (a long pause, the cooldown
  // towards steady state) a temperature depends on cells far away, GMRES stops short of it, and the Newton
  // test, which sees only small corrections, passes a state kelvins off. A steady bar of 50 cells ends
  // 1e-3 of its temperature drop off its own network with no limit, 2e-5 with this one (heat_test).
  co.max_step_s = 4.0 * median_tau;
  co.communicator = model.communicator();
  auto cvode = std::make_unique<Cvode>(model, t0, model.local(before), co);
  long steps = 0, rhs = 0, linear = 0;  // of the integrators replaced
  double t = t0;
  std::vector<double> now_all, between_all;  // across ranks: the whole state gathered
  std::vector<double> first_point;           // the state at the first Gauss-Legendre point of a step
  const auto healing_rate = [&](std::span<const double> state, std::uint32_t k) {
    return reptation.rate_per_s(0.5 * (state[cells_of[k][0]] + state[cells_of[k][1]]));
  };
  // The interfaces that heal over the step now ending: born (both cells) and with a warm cell; each once.
  // The integral goes on past 1 (full healing): how far past says how much colder the interface could be.
  // And the lumped cells warm enough for their inner interfaces to heal.
  const auto find_healing = [&](std::span<const double> start, std::span<const double> end) {
    const std::size_t born = model.born();
    for (std::size_t i = 0; i < born; ++i) warm[i] = std::max(start[i], end[i]) >= warm_c;
    healing_now.clear();
    lumps_healing_now.clear();
    for (std::size_t i = 0; i < born; ++i) {
      if (!warm[i]) continue;
      if (inner_first[i] != inner_first[i + 1]) lumps_healing_now.push_back(static_cast<std::uint32_t>(i));
      for (std::size_t e = cell_first[i]; e < cell_first[i + 1]; ++e) {
        const CellInterface& c = cell_interfaces[e];
        if (c.younger >= born) continue;
        if (c.other < i && warm[c.other]) continue;  // counted from the other cell
        healing_now.push_back(c.interface);
      }
    }
  };
  // Integrates to `target`: the healing over each step, and the samples in it.
  const auto advance = [&](double target) {
    if (target <= t) return;
    cvode->set_stop_time(target);
    while (t < target) {
      const double t_prev = t;
      t = cvode->step(target);
      const double half = 0.5 * (t - t_prev);
      const double mid = t_prev + half;
      const double offset = half / std::sqrt(3.0);
      // Across ranks, every rank gathers the whole state: what follows is the same on all of them.
      const std::span<const double> now = model.gather(cvode->state(), now_all);
      find_healing(before, now);
      if (!healing_now.empty() || !lumps_healing_now.empty()) {
        // Gauss-Legendre, two points: exact for cubics in t, as CVODE's interpolant is at low order. Each
        // interface and lumped cell is listed once, so they are shared out among threads as they are (an
        // exponential each, twice a step: a sixth of the stage when it ran on one thread), each summing its
        // two points in order as before.
        const std::span<const double> y0 = model.gather(cvode->interpolate(mid - offset), between_all);
        first_point.assign(y0.begin(), y0.end());
        const std::span<const double> y1 = model.gather(cvode->interpolate(mid + offset), between_all);
        for_range(0, healing_now.size(), [&](std::size_t e) {
          const std::uint32_t k = healing_now[e];
          integral[k] += half * healing_rate(first_point, k);
          integral[k] += half * healing_rate(y1, k);
        });
        for (const std::uint32_t g : lumps_healing_now) {
          lump_integral[g] += half * reptation.rate_per_s(first_point[g]);
          lump_integral[g] += half * reptation.rate_per_s(y1[g]);
        }
      }
      std::copy(now.begin(), now.end(), before.begin());
      while (next_snapshot < snapshot_times.size() && snapshot_times[next_snapshot].first <= t) {
        const auto [ts, request] = snapshot_times[next_snapshot++];
        snapshot(ts, request, ts == t ? now : model.gather(cvode->interpolate(ts), between_all));
      }
      while (next_sample <= t) {
        sample(next_sample,
               next_sample == t ? now : model.gather(cvode->interpolate(next_sample), between_all));
        next_sample += options.sample_interval_s;
      }
    }
  };
  for (std::size_t g = 1; g < groups.size(); ++g) {
    advance(groups[g].time_s);
    const bool lumped = options.lump && lump_settled(before);
    const bool grow = model_of[groups[g].end] > cap;
    if (grow) {  // by half at least, so the integrator is rebuilt a few dozen times in all
      const double lost = before[cap];
      std::copy(before.begin(), before.end() - 1, temps.begin());
      cap = std::min<std::size_t>(model_of[n], std::max<std::size_t>(model_of[groups[g].end], cap + cap / 2));
      before.assign(temps.begin(), temps.begin() + static_cast<std::ptrdiff_t>(cap));
      before.push_back(lost);
    }
    born_group(groups[g], before);
    if (grow || lumped) {
      steps += cvode->steps();
      rhs += cvode->rhs_evaluations();
      linear += cvode->linear_iterations();
      cvode.reset();
      model.set_capacity(cap);
      cvode = std::make_unique<Cvode>(model, t, model.local(before), co);
    }
    // The first step tries to reach the next group at once: the temperatures move slowly against the birth
    // interval (it is a fifth of a cell's time constant), so CVODE usually takes it.
    const double gap = g + 1 < groups.size() ? groups[g + 1].time_s - t : interval;
    cvode->reinit(t, model.local(before), std::max(gap, 1e-3 * interval));
    if (options.progress) options.progress((t - t0) / std::max(t_end - t0, 1e-9));
  }
  advance(t_end);
  if (options.progress) options.progress(1.0);
  flush_lumps();
  for (std::size_t k = 0; k < integral.size(); ++k) {
    result.interfaces[k].healing_integral = integral[k];
    result.interfaces[k].healing = std::min(1.0, std::pow(integral[k], 0.25));
  }
  for (InterfaceResult& r : result.interfaces)
    r.verdict = judge_interface(r.substrate_c, r.on_top, r.healing, material);

  std::copy(before.begin(), before.end() - 1, temps.begin());
  result.final_temp_c.resize(n);
  for (std::size_t i = 0; i < n; ++i) result.final_temp_c[i] = static_cast<float>(temps[model_of[i]]);
  for (std::size_t c = 0; c < n; ++c)  // mesh cells sharing their model cell
    result.lumped_cells += (c > 0 && model_of[c] == model_of[c - 1]) || model_of[c + 1] == model_of[c];
  result.model_cells = model_of[n];
  if (result.lumped_cells > 0)
    result.notes.push_back(fmt::format(
        "thermal: {} of {} cells lumped once settled ({} or more contacts below the top, within {:g} K of "
        "their neighbours along the bead), {} cells at the end; set thermal.lump: false to keep every cell",
        result.lumped_cells, n, options.lump_depth + 1, options.lump_tolerance_k, result.model_cells));
  result.energy_in_J = model.energy_in_J();
  result.energy_lost_J = before[cap];
  result.energy_stored_J = model.energy_stored_J(temps);
  const double scale = std::max(std::abs(result.energy_in_J),
                                std::abs(result.energy_lost_J) + std::abs(result.energy_stored_J));
  result.energy_balance_rel_error =
      scale > 0.0 ? std::abs(result.energy_in_J - result.energy_lost_J - result.energy_stored_J) / scale
                  : 0.0;
  result.ranks = model.communicator() != nullptr ? model.communicator()->size() : 1;
  result.steps = steps + cvode->steps();
  result.rhs_evaluations = rhs + cvode->rhs_evaluations();
  result.linear_iterations = linear + cvode->linear_iterations();
  return result;
}

}  // namespace beadtwin::thermal
