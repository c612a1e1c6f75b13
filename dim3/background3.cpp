// The generated background mesh (dim3/tet_mesh.h): a shifted cubic grid, each cube split into the
// 6 Kuhn (Freudenthal) tets around its main diagonal.
//
// Why Kuhn: every cube uses the same diagonal direction (from its corner (0,0,0) to (1,1,1)), so
// the split of a shared square face is the same seen from both cubes and the tets conform across
// cube faces without any bookkeeping. Tet (a, b, c) for a permutation of the axes is the path
// corner -> +e_a -> +e_b -> +e_c; det(v1 - v0, v2 - v0, v3 - v0) = h_a h_b h_c sign(a, b, c), so
// the odd permutations are turned by swapping v2 and v3. The lattice coordinates are rounded
// doubles, but every tet's corners are still corners of one axis-aligned cell with strictly
// increasing coordinates (asserted), so that sign is exact whatever the rounding.
//
// The grid is shifted off the box by a small odd fraction of h per axis (and per attempt) so that
// the lattice planes miss the round coordinates inputs tend to have (0, 0.5, 1, ...).
//
// Absurd sizes: a grid of more than kMaxTets tets (50 million) is refused with IMM_ASSERT
// (InvariantError, exit 1): the function returns a mesh, not a report, so the caller (CLI) must
// bound the resolution it passes; reaching the limit here is the caller's bug.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/huge_pages.h"
#include "dim3/tet_mesh.h"

namespace imm::dim3 {
namespace {

constexpr double kMaxTets = 50e6;

/// The shift of the grid origin, as a fraction of h, for one attempt and axis: odd decimals, so
/// that lattice planes avoid the round coordinates of typical inputs; different per axis so that
/// no lattice point lies on the box's diagonal planes either.
///
/// A retry must not repeat a contact. A contact (input vertex on a tet face, input edge through a
/// tet edge, tet vertex on an input triangle) survives every translation parallel to the face, to
/// both edges, or to the triangle; retries that moved along one direction only would meet it
/// again whenever that direction lies in such a plane. Moving along (1,1,1), the direction of
/// the Kuhn tets' long edges, did exactly that (issue 13: the unit tetrahedron failed at every
/// retry). So each retry adds attempt * kStep (mod 1) per axis: kStep = (1/g, 1/g^2, 1/g^3) with
/// g the plastic number (the R3 low-discrepancy sequence). Modulo the lattice, one retry moves the
/// grid by kStep h, whose components are independent over the rationals: it is parallel to no
/// lattice plane and no tet edge of the grid (their directions are rational), and lies in the
/// plane of an input triangle only if that triangle's normal is orthogonal to it.
double shift_fraction(int attempt, int axis) {
  constexpr double kStep[3] = {0.7548776662466927, 0.5698402909980532, 0.4301597090019468};
  const double first = 0.0123457 + 0.00731 * axis;  // attempt 0, as before
  return std::fmod(first + attempt * kStep[axis], 1.0);
}

}  // namespace

TetMesh make_grid_background(const Box3& box, int resolution, int attempt) {
  IMM_ASSERT(resolution >= 1, "grid resolution must be at least 1");
  IMM_ASSERT(attempt >= 0, "grid attempt must be non-negative");
  double longest = 0;
  for (int k = 0; k < 3; ++k) {
    IMM_ASSERT(std::isfinite(box.lo[k]) && std::isfinite(box.hi[k]) && box.lo[k] <= box.hi[k],
               "grid background needs a finite box with lo <= hi");
    longest = std::max(longest, box.hi[k] - box.lo[k]);
  }
  IMM_ASSERT(longest > 0 && std::isfinite(longest), "grid background needs a box of positive size");
  const double h = longest / resolution;

  // Per axis: lattice coordinates origin + i h for i = 0..cubes[k].
  std::array<std::vector<double>, 3> lattice;
  std::array<long long, 3> cubes{};
  double tet_count = 6;
  for (int k = 0; k < 3; ++k) {
    const double origin = box.lo[k] - h * (1 + shift_fraction(attempt, k));
    const double end = box.hi[k] + h;  // at least one cube of margin beyond hi
    const double estimate = std::ceil((end - origin) / h);
    IMM_ASSERT(std::isfinite(estimate) && estimate < kMaxTets,
               "grid background too large on axis " + std::to_string(k));
    long long n = std::max(1LL, static_cast<long long>(estimate));
    while (origin + static_cast<double>(n) * h < end) ++n;
    cubes[k] = n;
    tet_count *= static_cast<double>(n);
  }
  IMM_ASSERT(tet_count <= kMaxTets,
             "grid background of " + std::to_string(static_cast<long long>(tet_count)) +
                 " tets exceeds the limit of 50 million (resolution " + std::to_string(resolution) +
                 "): the caller must bound the resolution");
  for (int k = 0; k < 3; ++k) {
    const double origin = box.lo[k] - h * (1 + shift_fraction(attempt, k));
    lattice[k].resize(static_cast<std::size_t>(cubes[k]) + 1);
    for (long long i = 0; i <= cubes[k]; ++i) {
      lattice[k][i] = origin + static_cast<double>(i) * h;
      IMM_ASSERT(i == 0 || lattice[k][i] > lattice[k][i - 1],
                 "grid step h = " + std::to_string(h) +
                     " is below the double resolution of the coordinates on axis " +
                     std::to_string(k));
    }
  }

  const long long nx = cubes[0] + 1, ny = cubes[1] + 1, nz = cubes[2] + 1;
  TetMesh mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(nx * ny * nz));
  advise_huge_pages(mesh.vertices);  // written whole below (core/huge_pages.h)
  for (long long z = 0; z < nz; ++z) {
    for (long long y = 0; y < ny; ++y) {
      for (long long x = 0; x < nx; ++x)
        mesh.vertices.push_back({lattice[0][x], lattice[1][y], lattice[2][z]});
    }
  }
  auto vertex = [&](long long x, long long y, long long z) {
    return static_cast<int>(x + nx * (y + ny * z));
  };

  // The 6 Kuhn tets of the unit cube as corner masks (bit k: +1 along axis k), turned positive.
  std::array<std::array<int, 4>, 6> kuhn{};
  {
    const int permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                    {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int p = 0; p < 6; ++p) {
      const int a = permutations[p][0], b = permutations[p][1], c = permutations[p][2];
      std::array<int, 4> tet{0, 1 << a, (1 << a) | (1 << b), 7};
      // sign of the permutation (a, b, c): even when it is a rotation of (0, 1, 2)
      const bool even = (b == (a + 1) % 3) && (c == (b + 1) % 3);
      if (!even) std::swap(tet[2], tet[3]);
      kuhn[p] = tet;
    }
  }
  mesh.tets.reserve(static_cast<std::size_t>(tet_count));
  advise_huge_pages(mesh.tets);
  for (long long z = 0; z + 1 < nz; ++z) {
    for (long long y = 0; y + 1 < ny; ++y) {
      for (long long x = 0; x + 1 < nx; ++x) {
        for (const auto& tet : kuhn) {
          Tet out{};
          for (int k = 0; k < 4; ++k) {
            const int corner = tet[k];
            out[k] = vertex(x + (corner & 1), y + ((corner >> 1) & 1), z + ((corner >> 2) & 1));
          }
          mesh.tets.push_back(out);
        }
      }
    }
  }
  return mesh;
}

}  // namespace imm::dim3
