#include "thermal/wall_1d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"
#include "thermal/cvode.hpp"
#include "thermal/wall_1d_model.hpp"

namespace beadtwin::thermal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kAbsoluteZeroC = -273.15;

// Absolute tolerance on the healing integral H = D_h⁴ (dimensionless). D_h is read at 0.5-1, where an error
// of 1e-8 in H is below 1e-7 in D_h; the step cost of this tolerance is small (the temperatures set the
// steps).
constexpr double kHealingAbsTol = 1e-8;

// Points per integrator step at which the substrate temperature is read (CVODE's interpolant, of the order
// of the step) for its minimum, maximum and time average over a layer's deposition.
constexpr int kSubstratePointsPerStep = 4;

// Guard against an output that cannot fit in memory (a tiny sample interval over a long print).
constexpr double kMaxHistoryValues = 2e8;

// Collects every problem with the inputs before any work, then throws one InputError.
class Problems {
 public:
  // The first problem's key is the error's key; the others are named in the message.
  void add(const std::string& key, const std::string& message) {
    if (key_.empty()) {
      key_ = key;
      message_ = message;
    } else {
      message_ += "; " + key + " " + message;
    }
  }
  void positive(const std::string& key, double value) {
    if (!(std::isfinite(value) && value > 0.0)) add(key, fmt::format("must be positive, got {}", value));
  }
  void non_negative(const std::string& key, double value) {
    if (!(std::isfinite(value) && value >= 0.0)) add(key, fmt::format("must be >= 0, got {}", value));
  }
  void in_range(const std::string& key, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi)) add(key, fmt::format("must lie in [{}, {}], got {}", lo, hi, value));
  }
  void temperature(const std::string& key, double value) {
    if (!(std::isfinite(value) && value > kAbsoluteZeroC))
      add(key, fmt::format("must be a temperature above absolute zero (C), got {}", value));
  }
  void throw_if_any() const {
    if (!key_.empty()) throw InputError({}, key_, message_);
  }

 private:
  std::string key_;
  std::string message_;
};

void validate_layers(std::span<const Wall1dLayer> layers, Problems& problems) {
  if (layers.empty()) problems.add("layers", "must hold at least one layer");
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const Wall1dLayer& layer = layers[i];
    const std::string key = fmt::format("layers[{}]", i);
    problems.positive(key + ".height_mm", layer.height_mm);
    problems.positive(key + ".area_mm2", layer.area_mm2);
    problems.non_negative(key + ".perimeter_mm", layer.perimeter_mm);
    if (!std::isfinite(layer.z_top_mm)) problems.add(key + ".z_top_mm", "must be finite");
    if (!std::isfinite(layer.start_s)) problems.add(key + ".start_s", "must be finite");
    if (!(std::isfinite(layer.end_s) && layer.end_s >= layer.start_s))
      problems.add(key + ".end_s",
                   fmt::format("must be >= start_s ({} s), got {}", layer.start_s, layer.end_s));
    if (i > 0 && !(layer.start_s > layers[i - 1].start_s))
      problems.add(key + ".start_s",
                   fmt::format("must be later than the previous layer's start ({} s), got {}",
                               layers[i - 1].start_s, layer.start_s));
  }
}

void validate_material(const Material& m, Problems& problems) {
  problems.positive("material.density_kg_m3", m.density_kg_m3);
  if (m.specific_heat_by_temp.empty())
    problems.positive("material.specific_heat_J_kgK", m.specific_heat_J_kgK);
  for (std::size_t i = 0; i < m.specific_heat_by_temp.size(); ++i) {
    const auto& [temp_c, c_p] = m.specific_heat_by_temp[i];
    const std::string key = fmt::format("material.specific_heat_by_temp[{}]", i);
    problems.positive(key, c_p);
    if (!std::isfinite(temp_c) || (i > 0 && !(temp_c > m.specific_heat_by_temp[i - 1].first)))
      problems.add(key, fmt::format("temperatures must be finite and increase, got {} C", temp_c));
  }
  problems.positive("material.conductivity_through_W_mK", m.conductivity_through_W_mK);
  problems.in_range("material.emissivity", m.emissivity, 0.0, 1.0);
  problems.non_negative("material.deposition_temp_c", m.deposition_temp_c);
  problems.non_negative("material.healing_ref_temp_c", m.healing_ref_temp_c);
  problems.positive("material.reptation_time_ref_s", m.reptation_time_ref_s);
  problems.non_negative("material.healing_activation_J_mol", m.healing_activation_J_mol);
  problems.positive("material.wlf_c1", m.wlf_c1);
  problems.positive("material.wlf_c2_k", m.wlf_c2_k);
  problems.non_negative("material.wlf_range_k", m.wlf_range_k);
  problems.non_negative("material.healing_min_temp_c", m.healing_min_temp_c);
  problems.in_range("material.required_healing", m.required_healing, 0.0, 1.0);
}

void validate_environment(const Environment& env, Problems& problems) {
  problems.temperature("environment.ambient_c", env.ambient_c);
  problems.temperature("environment.bed_temp_c", env.bed_temp_c);
  problems.non_negative("environment.convection_W_m2K", env.convection_W_m2K);
  problems.non_negative("environment.bed_contact_W_m2K", env.bed_contact_W_m2K);
}

void validate_options(const Wall1dOptions& o, Problems& problems) {
  problems.positive("options.rel_tol", o.rel_tol);
  problems.positive("options.abs_tol_k", o.abs_tol_k);
  if (o.nodes_per_layer < 1)
    problems.add("options.nodes_per_layer", fmt::format("must be >= 1, got {}", o.nodes_per_layer));
  problems.non_negative("options.cooldown_s", o.cooldown_s);
  problems.positive("options.sample_interval_s", o.sample_interval_s);
}

double end_time_s(std::span<const Wall1dLayer> layers, const Wall1dOptions& options) {
  double last = layers.back().start_s;
  for (const Wall1dLayer& layer : layers) last = std::max(last, layer.end_s);
  return last + options.cooldown_s;
}

std::vector<double> sample_times(double t0, double t_end, double interval_s) {
  std::vector<double> times;
  const auto count = static_cast<std::size_t>(std::floor((t_end - t0) / interval_s));
  times.reserve(count + 2);
  for (std::size_t k = 0; k <= count; ++k) times.push_back(t0 + static_cast<double>(k) * interval_s);
  while (!times.empty() && times.back() > t_end) times.pop_back();
  if (times.empty() || times.back() < t_end) times.push_back(t_end);
  return times;
}

// Substrate temperature of one layer over its deposition [start_s, end_s].
struct SubstrateWindow {
  double end_s = 0;
  double at_start_c = 0, min_c = 0, max_c = 0;
  double surface_at_start_c = 0;  // its top face's, as the layer starts
  SupportResult support;          // whether the layers under it carry it, as it starts
  double integral_cs = 0;         // ∫ T dt, °C·s
  double last_t = 0, last_c = 0;
  bool open = false;

  void start(double t, double temp_c, double t_end) {
    end_s = t_end;
    at_start_c = min_c = max_c = last_c = temp_c;
    last_t = t;
    open = t_end > t;
  }
  void add(double t, double temp_c) {
    min_c = std::min(min_c, temp_c);
    max_c = std::max(max_c, temp_c);
    integral_cs += 0.5 * (t - last_t) * (temp_c + last_c);
    last_t = t;
    last_c = temp_c;
  }
  double mean_c(double start_s) const {
    return end_s > start_s ? integral_cs / (end_s - start_s) : at_start_c;
  }
};

// Whether the layers under `layer` (>= 1) carry it in state y: the column of node centres from the top of the
// layer below down to the table, or to the first node no longer soft.
SupportResult wall_support(const Support& support, const Wall1dModel& model,
                           std::span<const Wall1dLayer> layers, std::size_t layer,
                           std::span<const double> y) {
  const std::size_t n = model.nodes_per_layer();
  std::vector<double> z{layers[layer - 1].z_top_mm}, t{y[model.temp_index(layer - 1, n - 1)]};
  double bottom = layers[0].z_top_mm - layers[0].height_mm;  // the table, unless a node is no longer soft
  std::size_t deepest_soft = layer - 1;
  bool soft = true;
  for (std::size_t i = layer; soft && i-- > 0;) {
    const double dz = layers[i].height_mm / static_cast<double>(n);
    for (std::size_t j = n; soft && j-- > 0;) {
      z.push_back(layers[i].z_top_mm - (static_cast<double>(n - 1 - j) + 0.5) * dz);
      t.push_back(y[model.temp_index(i, j)]);
      soft = t.back() > support.softening_c();
      if (soft) deepest_soft = i;
      if (!soft) bottom = z.back() - 0.5 * dz;
    }
  }
  z.push_back(bottom);
  t.push_back(t.back());
  const Wall1dLayer& below = layers[layer - 1];
  const Wall1dLayer& l = layers[layer];
  const double width =
      below.perimeter_mm > 0.0 ? 2.0 * below.area_mm2 / below.perimeter_mm : std::sqrt(below.area_mm2);
  const double length = l.area_mm2 / std::max(width, 1e-9);
  const double speed = l.end_s > l.start_s ? length / (l.end_s - l.start_s) : 0.0;
  return support.judge_column(z, t, width, l.height_mm, speed, l.start_s - layers[deepest_soft].start_s);
}

// Reads what the result keeps out of the integration, step by step: the sampled layer temperatures and the
// substrate temperature during each layer's deposition.
class Recorder {
 public:
  Recorder(const Wall1dModel& model, const Support& support, std::span<const Wall1dLayer> layers,
           std::vector<double> times)
      : model_(model), support_(support), layers_(layers), times_(std::move(times)), windows_(layers.size()) {
    temps_.assign(layers.size(), std::vector<float>(times_.size(), std::numeric_limits<float>::quiet_NaN()));
  }

  // After layer `layer` is born at t with state y. Samples at exactly t see the new layer.
  void on_birth(std::size_t layer, double t, std::span<const double> y) {
    if (layer > 0) {
      windows_[layer].start(t, model_.substrate_temp_c(layer, y), layers_[layer].end_s);
      windows_[layer].surface_at_start_c = model_.substrate_surface_c(layer, y);
      windows_[layer].support = wall_support(support_, model_, layers_, layer, y);
    }
    while (next_ < times_.size() && times_[next_] <= t) record(next_++, y);
  }

  // After the integrator stepped from t_from to t_to (<= segment_end). Samples at the segment's end are
  // left to the next segment, which starts with a birth, unless this is the last segment.
  void on_step(double t_from, double t_to, double segment_end, bool last_segment, Cvode& cvode) {
    while (next_ < times_.size() && times_[next_] <= t_to && (last_segment || times_[next_] < segment_end)) {
      const double t = times_[next_];
      record(next_++, t == t_to ? cvode.state() : cvode.interpolate(t));
    }
    for (std::size_t i = 1; i < windows_.size(); ++i) {
      SubstrateWindow& w = windows_[i];
      if (!w.open) continue;
      const double hi = std::min(t_to, w.end_s);
      for (int j = 1; j <= kSubstratePointsPerStep && hi > t_from; ++j) {
        const double t =
            j == kSubstratePointsPerStep ? hi : t_from + (hi - t_from) * j / kSubstratePointsPerStep;
        w.add(t, model_.substrate_temp_c(i, t == t_to ? cvode.state() : cvode.interpolate(t)));
      }
      if (w.end_s <= t_to) w.open = false;
    }
  }

  const SubstrateWindow& window(std::size_t layer) const { return windows_[layer]; }
  std::vector<double> take_times() { return std::move(times_); }
  std::vector<std::vector<float>> take_temps() { return std::move(temps_); }

 private:
  void record(std::size_t sample, std::span<const double> y) {
    for (std::size_t i = 0; i < model_.born_count(); ++i)
      temps_[i][sample] = static_cast<float>(model_.layer_mean_temp_c(i, y));
  }

  const Wall1dModel& model_;
  const Support& support_;
  std::span<const Wall1dLayer> layers_;
  std::vector<double> times_;
  std::size_t next_ = 0;
  std::vector<std::vector<float>> temps_;
  std::vector<SubstrateWindow> windows_;
};

// Too hot is judged on the layers under the new one just before it touches them: they have to carry it and
// the roller. The reheating by the new layer afterwards is what fuses them, not a defect (and its peak
// depends on the node spacing, since the whole layer is born at once).
Verdict judge(const Wall1dLayerResult& r, const Material& material) {
  return judge_interface(r.support.too_hot(), r.healing, material);
}

}  // namespace

namespace {

// Integrates from the first birth to t_end, stepping from birth to birth: each birth is a discontinuity,
// so the integrator stops exactly at it, the layer is added and the integration restarts.
void integrate(std::span<const Wall1dLayer> layers, double t_end, Wall1dModel& model, Cvode& cvode,
               Recorder& recorder) {
  std::vector<double> y;
  for (std::size_t k = 0; k < layers.size(); ++k) {
    const double segment_start = layers[k].start_s;
    const bool last_segment = k + 1 == layers.size();
    const double segment_end = last_segment ? t_end : layers[k + 1].start_s;
    if (k > 0) {
      const std::span<const double> state = cvode.state();
      y.assign(state.begin(), state.end());
      model.birth(k, y);
      cvode.reinit(segment_start, y);
    }
    recorder.on_birth(k, segment_start, cvode.state());
    if (!(segment_end > segment_start)) continue;
    cvode.set_stop_time(segment_end);
    for (double t = segment_start; t < segment_end;) {
      const double t_next = cvode.step(segment_end);
      recorder.on_step(t, t_next, segment_end, last_segment, cvode);
      t = t_next;
    }
  }
}

Wall1dLayerResult layer_result(std::size_t layer, std::span<const Wall1dLayer> layers,
                               const Wall1dModel& model, const Recorder& recorder,
                               std::span<const double> y_end, const Material& material,
                               const Environment& env) {
  Wall1dLayerResult r;
  if (layer == 0) {
    const double table_c = env.bed_insulated ? env.ambient_c : env.bed_temp_c;
    r.substrate_min_c = r.substrate_mean_c = r.substrate_max_c = r.substrate_at_start_c = table_c;
    r.surface_at_start_c = table_c;
    r.healing = kNaN;
    r.verdict = Verdict::kNoInterface;
    return r;
  }
  const SubstrateWindow& w = recorder.window(layer);
  r.substrate_at_start_c = w.at_start_c;
  r.surface_at_start_c = w.surface_at_start_c;
  r.support = w.support;
  r.substrate_min_c = w.min_c;
  r.substrate_max_c = w.max_c;
  r.substrate_mean_c = w.mean_c(layers[layer].start_s);
  r.healing = std::min(1.0, std::pow(std::max(0.0, y_end[model.healing_index(layer)]), 0.25));
  r.verdict = judge(r, material);
  return r;
}

void fill_energy(const Wall1dModel& model, std::span<const double> y_end, Wall1dResult& result) {
  result.energy_in_J = model.energy_in_J();
  result.energy_lost_J = model.energy_lost_J(y_end);
  result.energy_stored_J = model.energy_stored_J(y_end);
  const double scale = std::max(std::abs(result.energy_in_J),
                                std::abs(result.energy_lost_J) + std::abs(result.energy_stored_J));
  const double residual = result.energy_in_J - result.energy_lost_J - result.energy_stored_J;
  result.energy_balance_rel_error = scale > 0.0 ? std::abs(residual) / scale : 0.0;
}

}  // namespace

Wall1dResult solve_wall_1d(std::span<const Wall1dLayer> layers, const Material& material,
                           const Environment& env, const Wall1dOptions& options) {
  Problems problems;
  validate_layers(layers, problems);
  validate_material(material, problems);
  validate_environment(env, problems);
  validate_options(options, problems);
  problems.throw_if_any();

  const double t0 = layers.front().start_s;
  const double t_end = end_time_s(layers, options);
  if ((t_end - t0) / options.sample_interval_s * static_cast<double>(layers.size()) > kMaxHistoryValues)
    throw InputError({}, "options.sample_interval_s",
                     fmt::format("sample interval {} s keeps too many values over {} s and {} layers",
                                 options.sample_interval_s, t_end - t0, layers.size()));

  Wall1dModel model(layers, material, env, options.nodes_per_layer, options.side_half_cell);
  model.set_tolerances(options.rel_tol, options.abs_tol_k, kHealingAbsTol);
  const Support support(material, options.support);
  Recorder recorder(model, support, layers, sample_times(t0, t_end, options.sample_interval_s));
  std::vector<double> y0 = model.initial_state();
  model.birth(0, y0);
  CvodeOptions cvode_options;
  cvode_options.upper_bandwidth = model.upper_bandwidth();
  cvode_options.lower_bandwidth = model.lower_bandwidth();
  Cvode cvode(model, t0, y0, cvode_options);
  integrate(layers, t_end, model, cvode, recorder);

  const std::span<const double> y_end = cvode.state();
  Wall1dResult result;
  result.end_time_s = t_end;
  result.steps = cvode.steps();
  result.layers.reserve(layers.size());
  for (std::size_t i = 0; i < layers.size(); ++i)
    result.layers.push_back(layer_result(i, layers, model, recorder, y_end, material, env));
  result.sample_times_s = recorder.take_times();
  result.layer_temp_c = recorder.take_temps();
  fill_energy(model, y_end, result);
  return result;
}

}  // namespace beadtwin::thermal
