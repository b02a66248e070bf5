#include "render/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <utility>

#include "core/error.hpp"

namespace beadtwin::render {
namespace {

// ---- CIELAB (CIE 15:2004, D65 white, the sRGB primaries of IEC 61966-2-1) --------------------------------

using Lab = std::array<double, 3>;

constexpr double kWhiteX = 0.95047, kWhiteY = 1.0, kWhiteZ = 1.08883;

double decode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double encode(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}
double lab_f(double t) {
  constexpr double kDelta = 6.0 / 29.0;
  return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29.0;
}
double lab_f_inverse(double f) {
  constexpr double kDelta = 6.0 / 29.0;
  return f > kDelta ? f * f * f : 3 * kDelta * kDelta * (f - 4.0 / 29.0);
}

Lab to_lab(Rgb c) {
  const double r = decode(c.r), g = decode(c.g), b = decode(c.b);
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  const double fx = lab_f(x / kWhiteX), fy = lab_f(y / kWhiteY), fz = lab_f(z / kWhiteZ);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

Rgb from_lab(const Lab& lab) {
  const double fy = (lab[0] + 16) / 116;
  const double x = kWhiteX * lab_f_inverse(fy + lab[1] / 500);
  const double y = kWhiteY * lab_f_inverse(fy);
  const double z = kWhiteZ * lab_f_inverse(fy - lab[2] / 200);
  const double r = 3.2404542 * x - 1.5371385 * y - 0.4985314 * z;
  const double g = -0.9692660 * x + 1.8760108 * y + 0.0415560 * z;
  const double b = 0.0556434 * x - 0.2040259 * y + 1.0572252 * z;
  return {static_cast<float>(encode(r)), static_cast<float>(encode(g)), static_cast<float>(encode(b))};
}

// A colour given as #RRGGBB, as the palettes are published.
constexpr Rgb hex(int rgb) {
  return {static_cast<float>((rgb >> 16) & 0xff) / 255.0f, static_cast<float>((rgb >> 8) & 0xff) / 255.0f,
          static_cast<float>(rgb & 0xff) / 255.0f};
}

// The sampled table: fine enough that linear interpolation between its entries in sRGB is within a
// thousandth of the CIELAB curve, so at() stays a lookup and a blend.
constexpr int kTableSize = 1024;

}  // namespace

ColourMap::ColourMap(std::string name, Kind kind, const std::vector<Stop>& stops)
    : name_(std::move(name)), kind_(kind) {
  BT_CHECK(stops.size() >= 2);
  BT_CHECK(stops.front().t == 0.0 && stops.back().t == 1.0);
  // Interpolated in CIELAB: its L* is close to perceived lightness, so between two samples the lightness
  // changes evenly and monotonically, as the maps were designed to (viridis and inferno in CAM02-UCS,
  // which CIELAB approximates well over these short steps). Interpolating in sRGB would bend the lightness
  // curve between samples, and linear light would brighten every midpoint — both visible on the diverging
  // map, whose nine samples are far apart.
  std::vector<Lab> labs;
  labs.reserve(stops.size());
  for (const Stop& s : stops) labs.push_back(to_lab(s.colour));

  auto table = std::make_shared<std::vector<Rgb>>(kTableSize);
  std::size_t segment = 0;
  for (int i = 0; i < kTableSize; ++i) {
    const double t = static_cast<double>(i) / (kTableSize - 1);
    while (segment + 2 < stops.size() && t > stops[segment + 1].t) ++segment;
    const double t0 = stops[segment].t, t1 = stops[segment + 1].t;
    const double f = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    Lab lab;
    for (int c = 0; c < 3; ++c) lab[c] = (1 - f) * labs[segment][c] + f * labs[segment + 1][c];
    (*table)[i] = from_lab(lab);
  }
  // The ends are the published colours exactly, not their round trip through CIELAB.
  table->front() = stops.front().colour;
  table->back() = stops.back().colour;
  table_ = std::move(table);
}

Rgb ColourMap::at(double t) const {
  if (std::isnan(t)) return kNoValueGrey;
  const double x = std::clamp(t, 0.0, 1.0) * (kTableSize - 1);
  const auto i = static_cast<std::size_t>(std::min(x, static_cast<double>(kTableSize - 2)));
  const auto f = static_cast<float>(x - static_cast<double>(i));
  const Rgb& a = (*table_)[i];
  const Rgb& b = (*table_)[i + 1];
  return {a.r + f * (b.r - a.r), a.g + f * (b.g - a.g), a.b + f * (b.b - a.b)};
}

// The sequential maps are matplotlib's (van der Walt & Smith 2015, "mpl-colormaps", CC0;
// lib/matplotlib/_cm_listed.py): of the published 256-entry tables, every eighth entry (0, 8, ... 248) and
// the last, placed at entry / 255. Between them the maps bend little, so CIELAB interpolation stays within
// one 8-bit step of the full table (colormap_test.cpp checks it at matplotlib's ten-colour samples).
ColourMap ColourMap::viridis() {
  static const ColourMap kMap(
      "viridis", Kind::kSequential,
      {{0.0 / 255, {0.267004f, 0.004874f, 0.329415f}},   {8.0 / 255, {0.277018f, 0.050344f, 0.375715f}},
       {16.0 / 255, {0.282327f, 0.094955f, 0.417331f}},  {24.0 / 255, {0.282884f, 0.135920f, 0.453427f}},
       {32.0 / 255, {0.278826f, 0.175490f, 0.483397f}},  {40.0 / 255, {0.270595f, 0.214069f, 0.507052f}},
       {48.0 / 255, {0.258965f, 0.251537f, 0.524736f}},  {56.0 / 255, {0.244972f, 0.287675f, 0.537260f}},
       {64.0 / 255, {0.229739f, 0.322361f, 0.545706f}},  {72.0 / 255, {0.214298f, 0.355619f, 0.551184f}},
       {80.0 / 255, {0.199430f, 0.387607f, 0.554642f}},  {88.0 / 255, {0.185556f, 0.418570f, 0.556753f}},
       {96.0 / 255, {0.172719f, 0.448791f, 0.557885f}},  {104.0 / 255, {0.160665f, 0.478540f, 0.558115f}},
       {112.0 / 255, {0.149039f, 0.508051f, 0.557250f}}, {120.0 / 255, {0.137770f, 0.537492f, 0.554906f}},
       {128.0 / 255, {0.127568f, 0.566949f, 0.550556f}}, {136.0 / 255, {0.120565f, 0.596422f, 0.543611f}},
       {144.0 / 255, {0.120638f, 0.625828f, 0.533488f}}, {152.0 / 255, {0.132268f, 0.655014f, 0.519661f}},
       {160.0 / 255, {0.157851f, 0.683765f, 0.501686f}}, {168.0 / 255, {0.196571f, 0.711827f, 0.479221f}},
       {176.0 / 255, {0.246070f, 0.738910f, 0.452024f}}, {184.0 / 255, {0.304148f, 0.764704f, 0.419943f}},
       {192.0 / 255, {0.369214f, 0.788888f, 0.382914f}}, {200.0 / 255, {0.440137f, 0.811138f, 0.340967f}},
       {208.0 / 255, {0.515992f, 0.831158f, 0.294279f}}, {216.0 / 255, {0.595839f, 0.848717f, 0.243329f}},
       {224.0 / 255, {0.678489f, 0.863742f, 0.189503f}}, {232.0 / 255, {0.762373f, 0.876424f, 0.137064f}},
       {240.0 / 255, {0.845561f, 0.887322f, 0.099702f}}, {248.0 / 255, {0.926106f, 0.897330f, 0.104071f}},
       {255.0 / 255, {0.993248f, 0.906157f, 0.143936f}}});
  return kMap;
}

ColourMap ColourMap::inferno() {
  static const ColourMap kMap(
      "inferno", Kind::kSequential,
      {{0.0 / 255, {0.001462f, 0.000466f, 0.013866f}},   {8.0 / 255, {0.013995f, 0.011225f, 0.071862f}},
       {16.0 / 255, {0.042253f, 0.028139f, 0.141141f}},  {24.0 / 255, {0.081962f, 0.043328f, 0.215289f}},
       {32.0 / 255, {0.129285f, 0.047293f, 0.290788f}},  {40.0 / 255, {0.183429f, 0.040329f, 0.354971f}},
       {48.0 / 255, {0.238273f, 0.036621f, 0.396353f}},  {56.0 / 255, {0.290763f, 0.045644f, 0.418637f}},
       {64.0 / 255, {0.341500f, 0.062325f, 0.429425f}},  {72.0 / 255, {0.391453f, 0.080927f, 0.433109f}},
       {80.0 / 255, {0.441207f, 0.099338f, 0.431594f}},  {88.0 / 255, {0.491022f, 0.117179f, 0.425552f}},
       {96.0 / 255, {0.540920f, 0.134729f, 0.415123f}},  {104.0 / 255, {0.590734f, 0.152563f, 0.400290f}},
       {112.0 / 255, {0.640135f, 0.171438f, 0.381065f}}, {120.0 / 255, {0.688653f, 0.192239f, 0.357603f}},
       {128.0 / 255, {0.735683f, 0.215906f, 0.330245f}}, {136.0 / 255, {0.780517f, 0.243327f, 0.299523f}},
       {144.0 / 255, {0.822386f, 0.275197f, 0.266085f}}, {152.0 / 255, {0.860533f, 0.311892f, 0.230606f}},
       {160.0 / 255, {0.894305f, 0.353399f, 0.193584f}}, {168.0 / 255, {0.923215f, 0.399359f, 0.155193f}},
       {176.0 / 255, {0.946965f, 0.449191f, 0.115272f}}, {184.0 / 255, {0.965397f, 0.502249f, 0.073859f}},
       {192.0 / 255, {0.978422f, 0.557937f, 0.034931f}}, {200.0 / 255, {0.985952f, 0.615750f, 0.025592f}},
       {208.0 / 255, {0.987874f, 0.675267f, 0.065257f}}, {216.0 / 255, {0.984075f, 0.736087f, 0.129527f}},
       {224.0 / 255, {0.974638f, 0.797692f, 0.206332f}}, {232.0 / 255, {0.960626f, 0.859069f, 0.298010f}},
       {240.0 / 255, {0.947594f, 0.917399f, 0.410665f}}, {248.0 / 255, {0.954529f, 0.965896f, 0.540361f}},
       {255.0 / 255, {0.988362f, 0.998364f, 0.644924f}}});
  return kMap;
}

// ColorBrewer RdBu with 9 classes (Brewer 2002, colorbrewer2.org), reversed. Of RdBu's 11 classes the two
// darkest (#053061, #67001F) are left out: on a shaded part they would sink into the shadows, and the
// 9-class ends keep both extremes at a similar lightness (L* about 44 and 38) so neither sign looks heavier.
ColourMap ColourMap::diverging() {
  constexpr auto hex = [](int rgb) {
    return Rgb{static_cast<float>((rgb >> 16) & 0xff) / 255.0f,
               static_cast<float>((rgb >> 8) & 0xff) / 255.0f, static_cast<float>(rgb & 0xff) / 255.0f};
  };
  static const ColourMap kMap("diverging", Kind::kDiverging,
                              {{0.0 / 8, hex(0x2166ac)},
                               {1.0 / 8, hex(0x4393c3)},
                               {2.0 / 8, hex(0x92c5de)},
                               {3.0 / 8, hex(0xd1e5f0)},
                               {4.0 / 8, hex(0xf7f7f7)},
                               {5.0 / 8, hex(0xfddbc7)},
                               {6.0 / 8, hex(0xf4a582)},
                               {7.0 / 8, hex(0xd6604d)},
                               {8.0 / 8, hex(0xb2182b)}});
  return kMap;
}

// Okabe & Ito (2008), "Color Universal Design": orange, sky blue, bluish green, yellow, blue, vermillion and
// reddish purple, without the black, which a shaded part or dark text would swallow. Ordered so that
// neighbouring indices (adjacent sections, successive layers) differ in both hue and lightness.
Rgb category_colour(int index) {
  static constexpr Rgb kPalette[] = {
      hex(0x0072B2),  // blue
      hex(0xE69F00),  // orange
      hex(0x009E73),  // bluish green
      hex(0xCC79A7),  // reddish purple
      hex(0x56B4E9),  // sky blue
      hex(0xD55E00),  // vermillion
      hex(0xF0E442),  // yellow
  };
  if (index < 0) return kNoValueGrey;
  return kPalette[static_cast<std::size_t>(index) % std::size(kPalette)];
}

double ScalarScale::fraction(double value) const {
  if (std::isnan(value) || !std::isfinite(lo) || !std::isfinite(hi))
    return std::numeric_limits<double>::quiet_NaN();
  if (lo == hi) return value < lo ? 0.0 : value > hi ? 1.0 : 0.5;
  return std::clamp((value - lo) / (hi - lo), 0.0, 1.0);
}

Rgb ScalarScale::colour(double value) const {
  return map.at(fraction(value));
}

namespace {

// k * m * 10^e as the decimal it stands for: the integer is exact, and so is 10^n for n <= 22, so one
// correctly rounded multiplication or division gives the double nearest the decimal (0.3, where
// 3 * 0.1 would give 0.30000000000000004).
double decimal(double km, int e) {
  return e >= 0 ? km * std::pow(10.0, e) : km / std::pow(10.0, -e);
}

struct Step {
  int m;  // 1, 2 or 5
  int e;  // step = m * 10^e
};

// The first and last multiple of `step` inside [lo, hi], as doubles (they may be too large for an
// integer), allowing a hair at either end so that a range given as decimals (0.1 .. 0.3) keeps the end
// ticks its decimals name.
std::pair<double, double> multiples(double lo, double hi, const Step& step) {
  const double s = decimal(step.m, step.e);
  constexpr double kSlack = 1e-9;
  return {std::ceil(lo / s - kSlack), std::floor(hi / s + kSlack)};
}

Step next_smaller(Step s) {
  if (s.m == 5) return {2, s.e};
  if (s.m == 2) return {1, s.e};
  return {5, s.e - 1};
}

}  // namespace

std::vector<double> nice_ticks(double lo, double hi, int max_count) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (lo > hi) std::swap(lo, hi);
  if (lo == hi) return {lo};
  const double span = hi - lo;
  if (!std::isfinite(span)) {
    // Wider than the largest double: tick a tenth of the range and scale back; still 1-2-5 steps.
    std::vector<double> ticks = nice_ticks(lo / 10, hi / 10, max_count);
    for (double& t : ticks) t = std::clamp(t * 10, lo, hi);
    return ticks;
  }
  max_count = std::clamp(max_count, 2, 10000);

  // Start from a step larger than the whole range (one tick at most) and make it smaller, 5 -> 2 -> 1 -> 0.5,
  // until one more would give more than max_count ticks. The count only grows as the step shrinks.
  Step step{1, static_cast<int>(std::ceil(std::log10(span))) + 1};
  Step best{0, 0};
  for (int guard = 0; guard < 400; ++guard) {
    const auto [first, last] = multiples(lo, hi, step);
    const double count = last - first + 1;
    if (count > max_count) {
      if (best.m == 0) best = step;  // none gave 2..max_count: the fewest ticks above one
      break;
    }
    if (count >= 2) best = step;
    step = next_smaller(step);
  }
  if (best.m == 0) return {lo, hi};

  const auto [first, last] = multiples(lo, hi, best);
  std::vector<double> ticks;
  const auto count = static_cast<long long>(last - first + 1);
  for (long long i = 0; i < count; ++i) {
    const double k = first + static_cast<double>(i);
    const double t = k == 0 ? 0.0 : std::clamp(decimal(k * best.m, best.e), lo, hi);
    if (ticks.empty() || t != ticks.back()) ticks.push_back(t);
  }
  if (ticks.size() < 2) return {lo, hi};
  return ticks;
}

namespace {

std::string print(const char* format, int digits, double value) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, digits, value);
  std::string s(buffer);
  if (s.front() == '-' && std::strtod(s.c_str(), nullptr) == 0.0) s.erase(0, 1);  // "-0.00" -> "0.00"
  return s;
}

// Labels for `values` (finite, sorted, distinct) in one printf notation ("%.*f" or "%.*e") with the fewest
// digits that keep every label within `tolerance` of its value and all labels distinct; empty when no
// number of digits does.
std::vector<std::string> shortest(const std::vector<double>& values, const char* format, double tolerance) {
  for (int digits = 0; digits <= 17; ++digits) {
    std::vector<std::string> labels;
    bool ok = true;
    for (const double v : values) {
      // Zero needs no exponent: "0", not "0e+00".
      labels.push_back(v == 0.0 && format[3] == 'e' ? "0" : print(format, digits, v));
      ok = ok && std::abs(std::strtod(labels.back().c_str(), nullptr) - v) <= tolerance;
      ok = ok && (labels.size() < 2 || labels.back() != labels[labels.size() - 2]);
    }
    if (ok) return labels;
  }
  return {};
}

std::size_t longest(const std::vector<std::string>& labels) {
  std::size_t n = 0;
  for (const auto& s : labels) n = std::max(n, s.size());
  return n;
}

}  // namespace

std::vector<std::string> tick_labels(const std::vector<double>& ticks) {
  std::vector<double> values;
  for (const double v : ticks)
    if (std::isfinite(v)) values.push_back(v == 0.0 ? 0.0 : v);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());

  // How closely a label must say its value: a thousandth of the smallest gap between ticks, or of the value
  // itself when there is only one.
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < values.size(); ++i) gap = std::min(gap, values[i] - values[i - 1]);
  const double tolerance = std::isfinite(gap) ? 1e-3 * gap
                           : values.empty()   ? 0.0
                                              : 1e-3 * std::abs(values.front());

  std::vector<std::string> labels = shortest(values, "%.*f", tolerance);
  const std::vector<std::string> scientific = shortest(values, "%.*e", tolerance);
  if (labels.empty() || (!scientific.empty() && longest(scientific) < longest(labels))) labels = scientific;
  if (labels.empty())  // no notation says them closely enough (a gap at the last digits of a double)
    for (const double v : values) labels.push_back(print("%.*g", 17, v));

  std::vector<std::string> out;
  out.reserve(ticks.size());
  for (const double v : ticks) {
    if (std::isnan(v)) {
      out.emplace_back("nan");
    } else if (std::isinf(v)) {
      out.emplace_back(v > 0 ? "inf" : "-inf");
    } else {
      const auto at = std::lower_bound(values.begin(), values.end(), v == 0.0 ? 0.0 : v) - values.begin();
      out.push_back(labels[static_cast<std::size_t>(at)]);
    }
  }
  return out;
}

}  // namespace beadtwin::render
