// The history recorder of the heat solve, internal to the thermal library (thermal/heat.hpp): the layers'
// mean temperatures every sample interval, and every cell's temperature at the snapshot times, taken from
// the integrator's state as the steps pass them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::thermal {

// Records the layers' temperatures and the snapshots as the integrator's steps pass their times.
class HistoryRecorder {
 public:
  // Samples of the `layer_count` toolpath layers from t0_s to t_end_s every options.sample_interval_s (> 0),
  // s; snapshots at options.snapshot_times_s, clamped to [t0_s, t_end_s]. The cells' layers and volumes
  // from `mesh`, which must outlive the recorder.
  HistoryRecorder(const ThermalMesh& mesh, std::size_t layer_count, double t0_s, double t_end_s,
                  const HeatOptions& options);

  // The model cells the states are indexed by: model_of[i] is mesh cell i's model cell (non-decreasing),
  // model_of.back() the model's cell count. Must outlive the recorder or the next call.
  void index(std::span<const std::uint32_t> model_of);

  // Records the snapshots, then the samples, due at or before `t`: `now` is the state (by model cell) at t,
  // state_at(time) the state at an earlier time within the step that just ended. `mesh_born` and
  // `model_born`: the mesh's and the model's cells born so far.
  template <class StateAt>
  void record_until(double t, std::span<const double> now, std::size_t mesh_born, std::size_t model_born,
                    const StateAt& state_at) {
    while (next_snapshot_ < snapshot_times_.size() && snapshot_times_[next_snapshot_].first <= t) {
      const auto [ts, request] = snapshot_times_[next_snapshot_++];
      snapshot(ts, request, ts == t ? now : state_at(ts), mesh_born);
    }
    while (next_sample_ <= t) {
      sample(next_sample_, next_sample_ == t ? now : state_at(next_sample_), model_born);
      next_sample_ += interval_s_;
    }
  }

  // Moves what was recorded into `result`: its sample times, layer temperatures and snapshots.
  void take(HeatResult& result);

 private:
  void snapshot(double t, std::size_t request, std::span<const double> y, std::size_t mesh_born);
  void sample(double t, std::span<const double> y, std::size_t model_born);

  const ThermalMesh& mesh_;
  std::size_t layer_count_;
  double interval_s_;
  double next_sample_;
  std::vector<std::pair<double, std::size_t>> snapshot_times_;  // (time, index of the request), in time order
  std::size_t next_snapshot_ = 0;
  std::span<const std::uint32_t> model_of_;
  // The layers' share of each model cell: (layer, volume), model cell g's at [part_first_[g], [g + 1]).
  std::vector<std::size_t> part_first_;
  std::vector<std::pair<std::uint32_t, double>> parts_;
  std::vector<double> layer_sum_, layer_volume_;  // scratch of sample
  std::vector<double> sample_times_s_;
  std::vector<std::vector<float>> layer_temp_c_;
  std::vector<TemperatureSnapshot> snapshots_;
};

}  // namespace beadtwin::thermal
