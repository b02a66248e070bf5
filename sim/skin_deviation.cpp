#include "sim/skin_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sim/triangle_sampling.hpp"

namespace beadtwin::sim {
namespace {

struct Sums {
  double weight = 0.0, sum = 0.0, sum_sq = 0.0;
  double min = std::numeric_limits<double>::infinity(), max = -std::numeric_limits<double>::infinity();
  std::size_t count = 0;

  void add(double value, double weight_mm2) {
    weight += weight_mm2;
    sum += weight_mm2 * value;
    sum_sq += weight_mm2 * value * value;
    min = std::min(min, value);
    max = std::max(max, value);
    ++count;
  }
  void add(const Sums& s) {
    weight += s.weight;
    sum += s.sum;
    sum_sq += s.sum_sq;
    min = std::min(min, s.min);
    max = std::max(max, s.max);
    count += s.count;
  }
};

}  // namespace

SkinDeviation measure_skin_deviation(const NearestTriangles& print, const CadField& cad, double spacing_mm,
                                     double band_mm, double lowest_z_mm) {
  constexpr std::size_t kBlock = 4096;
  std::vector<Sums> per_block((print.triangles() + kBlock - 1) / kBlock);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, per_block.size()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      const auto ca = cad.grid().getConstUnsafeAccessor();
                      for (std::size_t b = range.begin(); b < range.end(); ++b) {
                        Sums& sums = per_block[b];
                        const std::size_t end = std::min(print.triangles(), (b + 1) * kBlock);
                        for (std::size_t i = b * kBlock; i < end; ++i) {
                          const std::array<Eigen::Vector3d, 3> t = print.triangle(i);
                          sample_points(t[0], t[1], t[2], spacing_mm,
                                        [&](const Eigen::Vector3d& p, double area) {
                                          if (p.z() < lowest_z_mm) return;
                                          sums.add(cad.at(ca, p), area);
                                        });
                        }
                      }
                    });
  Sums total;
  for (const Sums& s : per_block) total.add(s);
  SkinDeviation out;
  out.samples = total.count;
  out.area_mm2 = total.weight;
  if (total.count == 0) return out;
  out.mean_mm = total.sum / total.weight;
  out.rms_mm = std::sqrt(total.sum_sq / total.weight);
  out.min_mm = total.min;
  out.max_mm = total.max;
  out.min_clamped = out.min_mm <= -band_mm;
  out.max_clamped = out.max_mm >= band_mm;
  return out;
}

}  // namespace beadtwin::sim
