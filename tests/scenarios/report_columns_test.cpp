// The variants table's columns (scenarios/report_columns.hpp): each a declared metric, a difference from the
// baseline in points for a fraction and in per cent otherwise, judged by which way the metric is better.
#include "scenarios/report_columns.hpp"

#include <gtest/gtest.h>

#include "scenarios/input/metrics.hpp"

namespace beadtwin::scenarios {
namespace {

const VariantColumn& column(std::string_view metric) {
  for (const VariantColumn& c : variant_columns())
    if (c.metric == metric) return c;
  throw std::runtime_error("no column for " + std::string(metric));
}

TEST(VariantColumns, EachIsADeclaredMetric) {
  for (const VariantColumn& c : variant_columns()) EXPECT_NO_THROW(metric_def(c.metric)) << c.metric;
}

TEST(VariantColumns, MarkDifferencesFromTheBaselineByWhichWayIsBetter) {
  Metrics base, v;
  base.print_time_s = 3600, v.print_time_s = 3960;
  base.porosity = 0.02, v.porosity = 0.015;
  base.interfaces = v.interfaces = 10;
  base.min_healing = 0.5, v.min_healing = 0.6;
  base.layer_time_s.mean = 200, v.layer_time_s.mean = 100;

  // Longer is worse, in per cent.
  const VariantCell time = variant_cell(column("print_time_s"), v, &base);
  EXPECT_EQ(time.text, "1:06:00");
  EXPECT_EQ(time.delta, "+10.0 %");
  EXPECT_EQ(time.judgement, -1);
  // A fraction differs in points; less porous is better.
  const VariantCell porosity = variant_cell(column("porosity"), v, &base);
  EXPECT_EQ(porosity.text, "1.50 %");
  EXPECT_EQ(porosity.delta, "-0.5 pt");
  EXPECT_EQ(porosity.judgement, +1);
  // More healing is better; a healing degree is no fraction of a whole: per cent.
  const VariantCell healing = variant_cell(column("interfaces.min_healing"), v, &base);
  EXPECT_EQ(healing.delta, "+20.0 %");
  EXPECT_EQ(healing.judgement, +1);
  // Neither way is better for a layer time: marked different, not judged.
  const VariantCell layer_time = variant_cell(column("layer_time_s.mean"), v, &base);
  EXPECT_EQ(layer_time.delta, "-50.0 %");
  EXPECT_EQ(layer_time.judgement, 0);

  // The baseline's own row, a difference too small to show, and a figure not measured.
  EXPECT_TRUE(variant_cell(column("print_time_s"), base, nullptr).delta.empty());
  v.print_time_s = 3601;
  EXPECT_TRUE(variant_cell(column("print_time_s"), v, &base).delta.empty());
  EXPECT_EQ(variant_cell(column("min_stock_mm"), v, &base).text, "—");
  v.interfaces = 0;
  EXPECT_EQ(variant_cell(column("interfaces.min_healing"), v, &base).text, "—");
}

}  // namespace
}  // namespace beadtwin::scenarios
