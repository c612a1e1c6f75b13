// Seeded generators of 2D curve sets and independent exact facts about them, for property tests.
//
// CGAL-free on purpose: the facts below (crossings, degeneracies, enclosed area, winding number
// of a point) are computed by brute force in GMP rationals, independently of the arrangement code
// they check (DESIGN §4, invariant 1; CONVENTIONS "property tests").
#pragma once

#include <cstdint>
#include <vector>

#include "core/rational.h"
#include "dim2/curves.h"

namespace imm::test_support {

// ---- generators (every random choice takes an explicit seed) ------------------------------

/// `vertices` points drawn uniformly from the integer grid {0, step, ..., (range-1)*step}^2:
/// a random polygon with many crossings (and often an inversion). Consecutive points differ.
dim2::Curve random_polygon(std::uint64_t seed, std::size_t vertices, int range, int step = 1);

/// A closed curve that winds `turns` times around the origin: vertex i at angle
/// (i + (1 + backtrack) u_i) times the mean step 2 pi turns / vertices (u_i uniform in [0, 1)) and
/// a random radius in [0.35, 1] radius. With backtrack = 0 the angle only increases, so every
/// winding number lies in 0..turns (a ray from the origin is always crossed counter-clockwise);
/// turns > 1 gives many crossings. backtrack > 0 lets neighbours swap angular order, so the curve
/// runs backwards in places (small loops, sometimes an inversion). Integer coordinates, multiples
/// of `step`, |x|, |y| <= radius * step.
dim2::Curve random_star_curve(std::uint64_t seed, std::size_t vertices, int radius, double backtrack,
                              int turns = 1, int step = 1);

/// A large curve with O(n) crossings for timing: two counter-clockwise turns around a circle of
/// radius ~1e7 with 2% radial noise, so the two passes cross each other about every few vertices;
/// windings 0..2, integer coordinates.
dim2::Curve wobbly_circle(std::uint64_t seed, std::size_t vertices);

// ---- independent exact facts ------------------------------------------------------------

/// Exact signed area enclosed by the curves (sum of the shoelace formula over all curves).
Rational signed_area(const dim2::CurveSet& curves);

/// What a brute-force O(n^2) scan over all segment pairs finds.
struct CrossingFacts {
  std::size_t proper_crossings = 0;  ///< segment pairs crossing at a point interior to both
  bool generic = true;               ///< no touching, overlap or triple point (see below)
  std::size_t coincident_vertices = 0;   ///< pairs of distinct vertices at the same point
  std::size_t vertex_on_segment = 0;     ///< vertex lying on a segment not incident to it
  std::size_t triple_points = 0;         ///< crossing points shared by 2+ crossing pairs
  /// Per curve, how many crossings lie on it (a self-crossing counts twice).
  std::vector<std::size_t> crossings_per_curve;
  /// Curve pairs (i < j) that cross each other at least once.
  std::vector<std::pair<std::size_t, std::size_t>> crossing_curves;
};
CrossingFacts crossing_facts(const dim2::CurveSet& curves);

/// Winding number of the curves around p, exactly. @pre p lies on no segment.
int winding_number(const dim2::CurveSet& curves, const dim2::Point& p);

/// True when p lies on some segment (exactly).
bool on_curves(const dim2::CurveSet& curves, const dim2::Point& p);

/// Number of connected components of the union of the curves (curves joined by crossings).
std::size_t curve_components(const dim2::CurveSet& curves, const CrossingFacts& facts);

}  // namespace imm::test_support
