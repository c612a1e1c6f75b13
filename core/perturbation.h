// An explicit, tiny, exactly represented and reproducible perturbation of an input's vertices,
// used to resolve exact contacts (DESIGN §5): a vertex on a facet, an edge through an edge,
// coplanar or collinear overlaps, coincident vertices, an intersection curve through a vertex.
//
// Why explicit and not symbolic: the perturbed input is an ordinary input of doubles, so every
// later step (cell complex, immersion search, clipping against a background, CSG baseline,
// embedding) decides exactly on one and the same generic input; a symbolic perturbation would
// have to be carried through every predicate of every step, including the meshing. The output
// is the exact answer for an input within `max_displacement` of the user's (below 2^-30 of the
// bounding-box diagonal by construction), which the reports state.
//
// Which way: every vertex moves mostly *inward* (against the outward normal of its star, taken
// from the orientation), plus a smaller pseudo-random part that breaks ties. So two solids that
// touch from outside (cubes sharing a face, a corner on a face, curves touching at a vertex)
// come apart by a thin gap rather than overlapping by a thin sliver, whatever the vertex order
// or the rotation of the input: they are separate solids, and the mesh keeps them unglued. The
// pseudo-random part is a pure function of (seed, a key of the vertex's geometry): the key is
// computed from the exact coordinates of the vertex and of its neighbours (the callers in dim2/
// and dim3/), so re-indexing the input does not change the perturbed geometry, and two
// coincident vertices of different parts get different offsets. Exactly identical parts (the same
// curve or surface twice) give equal keys to their corresponding vertices: distinguish_equal_keys
// numbers the vertices sharing a key in file order, so the copies get different offsets (a
// deterministic, thread-independent choice; only such repeated keys depend on the vertex order).
// The copies then cross each other generically: they overlap, as the input says, in many thin
// cells (two copies of a 400-gon cross 200 times), rather than coming apart by a gap.
//
// CGAL-free, header-only: shared by dim2/ (curves) and dim3/ (surfaces); no branch on the
// dimension.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace imm {

/// One attempt of the contact-resolving perturbation: a seed and the amplitude's exponent
/// relative to the input's scale (offsets are at most 2^-bits times the power of two that bounds
/// the bounding-box diagonal, per axis).
struct PerturbationAttempt {
  std::uint64_t seed = 1;
  int bits = 40;
};

/// The attempts tried in order until every exact decision is generic: small first (the result
/// stays closest to the input); larger ones give more random bits where the coordinates' own
/// precision swallows the smaller offsets (a model far from the origin). With the largest,
/// 2^-32, a vertex moves by less than sqrt(3) 2^-31 of the diagonal's power of two, i.e. below
/// 2^-30 of the diagonal.
inline std::vector<PerturbationAttempt> perturbation_schedule() {
  return {{1, 40}, {2, 40}, {3, 37}, {4, 37}, {5, 34}, {6, 34}, {7, 32}, {8, 32}};
}

/// The smallest power of two >= x (x > 0 and finite), or 1 when x is 0 (a single point).
inline double power_of_two_at_least(double x) {
  if (!(x > 0.0)) return 1.0;
  int e = 0;
  const double m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  return m == 0.5 ? std::ldexp(1.0, e - 1) : std::ldexp(1.0, e);
}

/// A 64-bit mix (splitmix64's finalizer).
inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// A key of a point's exact coordinates (their bit patterns; -0 and +0 alike).
template <std::size_t D>
std::uint64_t point_key(const std::array<double, D>& p) {
  std::uint64_t h = 0x51ED270B27D5ull;
  for (std::size_t d = 0; d < D; ++d) {
    const double x = p[d] == 0.0 ? 0.0 : p[d];
    std::uint64_t bits = 0;
    std::memcpy(&bits, &x, sizeof bits);
    h = mix64(h ^ bits);
  }
  return h;
}

/// Makes repeated keys distinct: of the vertices sharing a key, the k-th in index order (k >= 1)
/// gets the key mixed with k; the first keeps it, so inputs without repeated keys are unchanged.
inline void distinguish_equal_keys(std::vector<std::uint64_t>& keys) {
  std::vector<std::size_t> order(keys.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return keys[a] < keys[b] || (keys[a] == keys[b] && a < b);
  });
  const std::vector<std::uint64_t> original = keys;
  for (std::size_t k = 1, rank = 0; k < order.size(); ++k) {
    rank = original[order[k]] == original[order[k - 1]] ? rank + 1 : 0;
    if (rank > 0) keys[order[k]] = mix64(original[order[k]] ^ mix64(0xC0FFEE00ull + rank));
  }
}

/// A reproducible value in [-1, 1], a multiple of 2^-20, from (seed, key, axis).
inline double perturbation_unit(std::uint64_t seed, std::uint64_t key, unsigned axis) {
  const std::uint64_t z = mix64(mix64(seed * 0xD1B54A32D192ED03ull ^ key) + axis);
  const auto k = static_cast<std::int64_t>(z >> 43);  // 21 bits: [0, 2^21)
  return std::ldexp(static_cast<double>(k - (std::int64_t{1} << 20)), -20);
}

/// The bounding-box diagonal of points in doubles (display and scale only, never a decision).
template <std::size_t D>
double diagonal_of(const std::vector<std::array<double, D>>& points) {
  if (points.empty()) return 0.0;
  std::array<double, D> lo = points.front(), hi = points.front();
  for (const auto& p : points)
    for (std::size_t d = 0; d < D; ++d) {
      lo[d] = std::min(lo[d], p[d]);
      hi[d] = std::max(hi[d], p[d]);
    }
  double s = 0.0;
  for (std::size_t d = 0; d < D; ++d) s += (hi[d] - lo[d]) * (hi[d] - lo[d]);
  return std::sqrt(s);
}

/// What a perturbation did to an input.
struct PerturbationSummary {
  PerturbationAttempt attempt;
  double amplitude = 0.0;         ///< bound on every offset (a power of two)
  double diagonal = 0.0;          ///< bounding-box diagonal of the input
  double max_displacement = 0.0;  ///< largest Euclidean distance a vertex moved
  std::size_t moved_vertices = 0; ///< vertices whose perturbed position differs from the input
};

/// Perturbs every point: point i moves by amplitude (inward[i] / 2 + u / 4), u a vector of
/// perturbation_unit(seed, keys[i], axis); the result is rounded to doubles (see the file comment).
/// @param[in,out] points  #V points of dimension D, moved in place
/// @param[in] inward      #V directions, unit or zero (where the star has no defined normal)
/// @param[in] keys        #V geometric keys (point_key of the point mixed with its neighbours')
/// @return the summary (amplitude = 2^-bits * power_of_two_at_least(diagonal))
template <std::size_t D>
PerturbationSummary perturb_points(std::vector<std::array<double, D>>& points,
                                   const std::vector<std::array<double, D>>& inward,
                                   const std::vector<std::uint64_t>& keys, const PerturbationAttempt& attempt) {
  PerturbationSummary s;
  s.attempt = attempt;
  s.diagonal = diagonal_of(points);
  s.amplitude = std::ldexp(power_of_two_at_least(s.diagonal), -attempt.bits);
  for (std::size_t i = 0; i < points.size(); ++i) {
    double moved2 = 0.0;
    for (std::size_t d = 0; d < D; ++d) {
      const double x = points[i][d];
      const double u = perturbation_unit(attempt.seed, keys[i], static_cast<unsigned>(d));
      const double y = x + s.amplitude * (0.5 * inward[i][d] + 0.25 * u);
      points[i][d] = y;
      moved2 += (y - x) * (y - x);
    }
    if (moved2 > 0.0) ++s.moved_vertices;
    s.max_displacement = std::max(s.max_displacement, std::sqrt(moved2));
  }
  return s;
}

}  // namespace imm
