#include "io/bounding_box_scale.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "math/number_text.hpp"

namespace dipc {

std::array<double, 3> bounding_box_extent(const std::vector<std::array<double, 3>>& points) {
  if (points.empty()) return {0, 0, 0};
  std::array<double, 3> lo = points[0], hi = points[0];
  for (const std::array<double, 3>& p : points)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
  return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
}

std::array<double, 3> dimension_factors(const std::optional<std::array<double, 3>>& dimensions,
                                        const std::vector<std::array<double, 3>>& points) {
  if (!dimensions) return {1, 1, 1};
  const std::array<double, 3> extent = bounding_box_extent(points);
  std::array<double, 3> f;
  for (int c = 0; c < 3; ++c) {
    const double d = (*dimensions)[c];
    if (d == 0 && extent[c] > 0)
      throw std::invalid_argument(std::string("0 along ") + char('x' + c) + ", where the mesh extends " +
                                  format_number(extent[c]) +
                                  ": it would flatten the mesh (give 0 only for an axis along which the mesh is flat)");
    f[c] = extent[c] > 0 ? d / extent[c] : d;
  }
  return f;
}

}  // namespace dipc
