#include "thermal/history.hpp"

#include <algorithm>
#include <limits>

namespace beadtwin::thermal {

HistoryRecorder::HistoryRecorder(const ThermalMesh& mesh, std::size_t layer_count, double t0_s,
                                 double t_end_s, const HeatOptions& options)
    : mesh_(mesh),
      layer_count_(layer_count),
      interval_s_(options.sample_interval_s),
      next_sample_(t0_s),
      layer_sum_(layer_count),
      layer_volume_(layer_count),
      layer_temp_c_(layer_count) {
  for (std::size_t k = 0; k < options.snapshot_times_s.size(); ++k)
    snapshot_times_.emplace_back(std::clamp(options.snapshot_times_s[k], t0_s, t_end_s), k);
  std::sort(snapshot_times_.begin(), snapshot_times_.end());
}

void HistoryRecorder::index(std::span<const std::uint32_t> model_of) {
  model_of_ = model_of;
  const std::size_t m = model_of.back();
  part_first_.assign(m + 1, 0);
  parts_.clear();
  std::uint32_t last = 0;
  for (std::size_t i = 0; i < mesh_.cells.size(); ++i) {
    const int layer = mesh_.cells[i].layer;
    if (layer < 0 || static_cast<std::size_t>(layer) >= layer_count_) continue;
    const std::uint32_t g = model_of[i];
    // A model cell's mesh cells are consecutive: its entries of one layer (most have one) are merged.
    if (!parts_.empty() && last == g && parts_.back().first == static_cast<std::uint32_t>(layer)) {
      parts_.back().second += mesh_.cells[i].volume_mm3;
    } else {
      parts_.emplace_back(static_cast<std::uint32_t>(layer), mesh_.cells[i].volume_mm3);
      ++part_first_[g + 1];
    }
    last = g;
  }
  for (std::size_t g = 0; g < m; ++g) part_first_[g + 1] += part_first_[g];
}

void HistoryRecorder::snapshot(double t, std::size_t request, std::span<const double> y,
                               std::size_t mesh_born) {
  TemperatureSnapshot s;
  s.time_s = t;
  s.request = request;
  s.temp_c.assign(mesh_.cells.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < mesh_born; ++i) s.temp_c[i] = static_cast<float>(y[model_of_[i]]);
  snapshots_.push_back(std::move(s));
}

void HistoryRecorder::sample(double t, std::span<const double> y, std::size_t model_born) {
  std::fill(layer_sum_.begin(), layer_sum_.end(), 0.0);
  std::fill(layer_volume_.begin(), layer_volume_.end(), 0.0);
  for (std::size_t g = 0; g < model_born; ++g)
    for (std::size_t e = part_first_[g]; e < part_first_[g + 1]; ++e) {
      layer_sum_[parts_[e].first] += parts_[e].second * y[g];
      layer_volume_[parts_[e].first] += parts_[e].second;
    }
  sample_times_s_.push_back(t);
  for (std::size_t k = 0; k < layer_count_; ++k)
    layer_temp_c_[k].push_back(layer_volume_[k] > 0.0 ? static_cast<float>(layer_sum_[k] / layer_volume_[k])
                                                      : std::numeric_limits<float>::quiet_NaN());
}

void HistoryRecorder::take(HeatResult& result) {
  result.sample_times_s = std::move(sample_times_s_);
  result.layer_temp_c = std::move(layer_temp_c_);
  result.snapshots = std::move(snapshots_);
}

}  // namespace beadtwin::thermal
