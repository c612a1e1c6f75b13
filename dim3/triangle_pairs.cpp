#include "dim3/triangle_pairs.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>

namespace imm::dim3 {

std::vector<std::array<std::uint32_t, 2>> overlapping_triangle_pairs(const Surface& surface) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<Box> boxes;
  boxes.reserve(surface.triangle_count());
  for (std::uint32_t t = 0; t < surface.triangle_count(); ++t) {
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = hi[d] = surface.vertices[surface.triangles[t][0]][d];
      for (int k = 1; k < 3; ++k) {
        lo[d] = std::min(lo[d], surface.vertices[surface.triangles[t][k]][d]);
        hi[d] = std::max(hi[d], surface.vertices[surface.triangles[t][k]][d]);
      }
    }
    boxes.emplace_back(lo, hi, t);
  }
  std::vector<std::array<std::uint32_t, 2>> pairs;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    pairs.push_back({std::min(a.info(), b.info()), std::max(a.info(), b.info())});
  });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace imm::dim3
