// Display colours for cluster labels, so that a labelled PLY opens coloured in any viewer.
#pragma once

#include <cstdint>

namespace fq::io {

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
};

/// Colour of cluster `label`: hue steps by the golden ratio (so consecutive labels, and
/// any small set of labels, get well-separated hues), with saturation and value cycling
/// over three levels to tell apart labels whose hues come close. Deterministic: the same
/// label always gets the same colour, whatever the number of clusters.
Rgb8 cluster_color(uint32_t label);

}  // namespace fq::io
