#include "io/cluster_colors.h"

#include <cmath>

namespace fq::io {

namespace {

constexpr double kGoldenRatioConjugate = 0.6180339887498949;
constexpr double kSaturation[3] = {0.75, 0.55, 0.95};
constexpr double kValue[3] = {0.95, 0.80, 0.65};

uint8_t to_byte(double c) { return static_cast<uint8_t>(std::lround(255.0 * c)); }

/// HSV with h in [0, 1) to RGB.
Rgb8 hsv_to_rgb(double h, double s, double v) {
  const double h6 = h * 6.0;
  const int sector = static_cast<int>(h6) % 6;
  const double f = h6 - std::floor(h6);
  const double p = v * (1.0 - s), q = v * (1.0 - s * f), t = v * (1.0 - s * (1.0 - f));
  switch (sector) {
    case 0:
      return {to_byte(v), to_byte(t), to_byte(p)};
    case 1:
      return {to_byte(q), to_byte(v), to_byte(p)};
    case 2:
      return {to_byte(p), to_byte(v), to_byte(t)};
    case 3:
      return {to_byte(p), to_byte(q), to_byte(v)};
    case 4:
      return {to_byte(t), to_byte(p), to_byte(v)};
    default:
      return {to_byte(v), to_byte(p), to_byte(q)};
  }
}

}  // namespace

Rgb8 cluster_color(uint32_t label) {
  // Fractional part of label * phi^-1; done in double, exact enough for any uint32 label.
  const double x = label * kGoldenRatioConjugate;
  const double hue = x - std::floor(x);
  const int level = static_cast<int>(label % 3);
  return hsv_to_rgb(hue, kSaturation[level], kValue[level]);
}

}  // namespace fq::io
