#include "dim3/triangle_pairs.h"

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>

#include "core/parallel.h"

namespace imm::dim3 {

namespace {

struct TriangleBox {
  double lo[3];
  double hi[3];
};

TriangleBox triangle_box(const Surface& surface, std::size_t t) {
  TriangleBox b{};
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = b.hi[d] = surface.vertices[surface.triangles[t][0]][d];
    for (int k = 1; k < 3; ++k) {
      b.lo[d] = std::min(b.lo[d], surface.vertices[surface.triangles[t][k]][d]);
      b.hi[d] = std::max(b.hi[d], surface.vertices[surface.triangles[t][k]][d]);
    }
  }
  return b;
}

bool overlap(const TriangleBox& a, const TriangleBox& b) {
  for (int d = 0; d < 3; ++d)
    if (a.hi[d] < b.lo[d] || b.hi[d] < a.lo[d]) return false;
  return true;
}

/// CGAL's box_self_intersection_d, for the inputs the grid below declines.
std::vector<std::array<std::uint32_t, 2>> pairs_by_box_intersection(const std::vector<TriangleBox>& boxes) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<Box> cgal_boxes;
  cgal_boxes.reserve(boxes.size());
  for (std::uint32_t t = 0; t < boxes.size(); ++t) {
    TriangleBox b = boxes[t];
    cgal_boxes.emplace_back(b.lo, b.hi, t);
  }
  std::vector<std::array<std::uint32_t, 2>> pairs;
  CGAL::box_self_intersection_d(cgal_boxes.begin(), cgal_boxes.end(), [&](const Box& a, const Box& b) {
    pairs.push_back({std::min(a.info(), b.info()), std::max(a.info(), b.info())});
  });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace

std::vector<std::array<std::uint32_t, 2>> overlapping_triangle_pairs(const Surface& surface, unsigned threads) {
  const std::size_t n = surface.triangle_count();
  threads = resolve_threads(threads);
  std::vector<TriangleBox> boxes(n);
  parallel_blocks(threads, n, 8192, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) boxes[t] = triangle_box(surface, t);
  });
  if (n < 2) return {};
  // A uniform grid of cells about the box size: every triangle is listed in the cells its
  // box meets, and a pair is reported from the one cell holding the corner max(lo_a, lo_b) of
  // the boxes' intersection (cell indices are monotone in the coordinate, so that cell is in
  // both boxes' ranges): each overlapping pair exactly once, without a global sort.
  double lo[3], hi[3], extent = 0.0;
  for (int d = 0; d < 3; ++d) {
    lo[d] = boxes[0].lo[d];
    hi[d] = boxes[0].hi[d];
  }
  for (const TriangleBox& b : boxes) {
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], b.lo[d]);
      hi[d] = std::max(hi[d], b.hi[d]);
    }
    extent += std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
  }
  // Cells of twice the mean box size (measured on the quintuple torus: 1x, 1.5x, 2x, 3x cost
  // 31, 27, 27, 30 ms CPU): fewer cells per box, a few more boxes per cell.
  double cell = 2.0 * extent / static_cast<double>(n);
  const double span[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  if (!std::isfinite(cell) || !std::isfinite(span[0]) || !std::isfinite(span[1]) || !std::isfinite(span[2]))
    return pairs_by_box_intersection(boxes);
  const double largest = std::max({span[0], span[1], span[2]});
  if (!(cell > 0.0)) cell = largest > 0.0 ? largest : 1.0;
  const double budget = 2.0 * static_cast<double>(n);  // cells
  while ((span[0] / cell + 1) * (span[1] / cell + 1) * (span[2] / cell + 1) > budget) cell *= 1.25;
  std::size_t dims[3];
  for (int d = 0; d < 3; ++d) dims[d] = static_cast<std::size_t>(span[d] / cell) + 1;
  const auto index = [&](double x, int d) {
    const double i = std::floor((x - lo[d]) / cell);
    return static_cast<std::size_t>(std::clamp(i, 0.0, static_cast<double>(dims[d] - 1)));
  };
  const std::size_t cells = dims[0] * dims[1] * dims[2];
  const auto cell_of = [&](const double* p) { return (index(p[0], 0) * dims[1] + index(p[1], 1)) * dims[2] + index(p[2], 2); };
  // body(cell) for every cell box `b` meets.
  const auto for_each_cell = [&](const TriangleBox& b, const auto& body) {
    for (std::size_t i = index(b.lo[0], 0); i <= index(b.hi[0], 0); ++i)
      for (std::size_t j = index(b.lo[1], 1); j <= index(b.hi[1], 1); ++j)
        for (std::size_t k = index(b.lo[2], 2); k <= index(b.hi[2], 2); ++k) body((i * dims[1] + j) * dims[2] + k);
  };
  // Cells per triangle; a few very large triangles over many cells are fine, many are not: then
  // CGAL's segment tree, which does not depend on the sizes.
  std::vector<std::uint32_t> cell_first(cells + 1, 0);
  std::size_t listed = 0;
  for (const TriangleBox& b : boxes) {
    std::size_t count = 1;
    for (int d = 0; d < 3; ++d) count *= index(b.hi[d], d) - index(b.lo[d], d) + 1;
    listed += count;
    if (listed > 32 * n + 1024) return pairs_by_box_intersection(boxes);
  }
  for (const TriangleBox& b : boxes) for_each_cell(b, [&](std::size_t c) { ++cell_first[c + 1]; });
  // The scan below tests every pair of boxes sharing a cell: about the sum over cells of the
  // square of their box counts. Clustered or elongated inputs (a fine cluster beside one large
  // triangle, long slivers along one axis) crowd most boxes into a few cells and would make it
  // quadratic: then the segment tree as well.
  double tests = 0.0;
  for (std::size_t c = 1; c <= cells; ++c) tests += static_cast<double>(cell_first[c]) * cell_first[c];
  if (tests > 256.0 * static_cast<double>(n) + 1e6) return pairs_by_box_intersection(boxes);
  for (std::size_t c = 0; c < cells; ++c) cell_first[c + 1] += cell_first[c];
  std::vector<std::uint32_t> cell_triangles(listed), next(cell_first.begin(), cell_first.end() - 1);
  for (std::uint32_t t = 0; t < n; ++t) for_each_cell(boxes[t], [&](std::size_t c) { cell_triangles[next[c]++] = t; });
  // Per block of consecutive triangles a, the pairs (a, b > a) sorted: concatenated in block
  // order they are the sorted list.
  constexpr std::size_t kBlock = 1024;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<std::array<std::uint32_t, 2>>> found(blocks);
  parallel_for(threads, blocks, [&](std::size_t block, unsigned) {
    // Collected in a local vector: neighbouring blocks' vector headers share a cache line.
    std::vector<std::array<std::uint32_t, 2>> out;
    for (std::size_t a = block * kBlock; a < std::min(n, (block + 1) * kBlock); ++a) {
      const TriangleBox& ba = boxes[a];
      const std::size_t first = out.size();
      for_each_cell(ba, [&](std::size_t c) {
        for (std::uint32_t x = cell_first[c]; x < cell_first[c + 1]; ++x) {
          const std::uint32_t b = cell_triangles[x];
          if (b <= a || !overlap(ba, boxes[b])) continue;
          const TriangleBox& bb = boxes[b];
          const double corner[3] = {std::max(ba.lo[0], bb.lo[0]), std::max(ba.lo[1], bb.lo[1]), std::max(ba.lo[2], bb.lo[2])};
          if (cell_of(corner) != c) continue;  // reported from the cell holding the corner
          out.push_back({static_cast<std::uint32_t>(a), b});
        }
      });
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
    }
    found[block] = std::move(out);
  }, 1);
  std::size_t total = 0;
  for (const auto& list : found) total += list.size();
  std::vector<std::array<std::uint32_t, 2>> pairs;
  pairs.reserve(total);
  for (const auto& list : found) pairs.insert(pairs.end(), list.begin(), list.end());
  return pairs;
}

}  // namespace imm::dim3
