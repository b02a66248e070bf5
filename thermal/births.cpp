#include "thermal/births.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace beadtwin::thermal {

BirthSchedule plan_births(std::span<const ThermalCell> cells, double median_time_constant_s,
                          const HeatOptions& options) {
  BirthSchedule s;
  s.automatic_interval_s = 0.2 * median_time_constant_s;
  double interval = options.birth_interval_s > 0.0 ? options.birth_interval_s : s.automatic_interval_s;
  if (options.birth_interval_s <= 0.0) {  // at most about max_automatic_birth_events: each group spans one
    const double span = cells.back().birth_s - cells.front().birth_s;
    interval = std::max(
        interval, span / static_cast<double>(std::max<std::size_t>(options.max_automatic_birth_events, 1)));
    if (interval > s.automatic_interval_s)
      s.note = fmt::format(
          "thermal birth interval {:.3g} s instead of {:.3g} s (a fifth of the beads' median time constant), "
          "so that the print's cells are born in at most about {} events; set thermal.birth_interval to "
          "choose",
          interval, s.automatic_interval_s, options.max_automatic_birth_events);
  }
  s.interval_s = interval;
  const std::size_t n = cells.size();
  for (std::size_t i = 0; i < n;) {
    const double first = cells[i].birth_s;
    std::size_t j = i;
    while (j < n && cells[j].birth_s <= first + interval) ++j;
    s.groups.push_back({j, 0.5 * (first + cells[j - 1].birth_s)});
    i = j;
  }
  return s;
}

}  // namespace beadtwin::thermal
