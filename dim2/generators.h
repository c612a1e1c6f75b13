// Procedural 2D inputs (`immerse generate`): the curves of the paper's figures, curves with known
// answers, and families that scale (issue 2, item 7).
//
// CGAL-free. Every generator returns integer coordinates (exactly representable doubles, so the
// exact arrangement sees exactly what was generated), and every output is GENERIC in the paper's
// sense (§3 "non-degenerate"): no collinear overlap, no vertex on another segment, no point where
// three or more segments meet. Fixed shapes were checked once (tests/dim2/generators_test.cpp);
// seeded random shapes are checked exactly on every call and re-drawn from a derived seed until
// generic.
//
// Conventions: counter-clockwise outer curves (winding +1 inside); the curve's left is the inner
// (negative) side of a patch (core/cell_complex.h).
//
// Several shapes are built from *Seifert circles*: disjoint oriented circles joined pairwise at
// chosen angles. Where two joined strands run in the same direction the join is a crossing,
// where they run in opposite directions it is a thin band (a connected sum without crossing).
// Smoothing every crossing of the result gives back the circles, so the turning number is
// (#counter-clockwise circles - #clockwise circles) and the winding number of a region is the
// signed number of circles around it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/generator_registry.h"
#include "dim2/curves.h"

namespace imm::dim2 {

// ---- the registry (`immerse generate --list`; core/generator_registry.h) -----------------------

/// Every curve generator by name, in the order `--list` prints them (dim2/generator_registry.cpp):
/// find(name), infos(), summaries() for the list.
const GeneratorRegistry<CurveSet>& curve_registry();

struct GenerateResult {
  CurveSet curves;
  std::string error;  ///< unknown name, bad parameter count or range
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Runs a generator by name. `arguments` are the parameters in order, either plain integers
/// ("3") or "name=value"; missing ones take their defaults.
GenerateResult generate(std::string_view name, const std::vector<std::string>& arguments);

// ---- the paper's figures -------------------------------------------------------------------

/// Fig. 5: a square band hooked over its own start (a "hook"): 2 crossings, windings 0..2
/// with a bounded hole of winding 0; the largest cell (winding 1) self-touches at both arcs.
/// 1 immersion.
CurveSet fig5();

/// Fig. 6: the Milnor-type doodle with two lobes, doodle(2): 6 crossings, windings 0..3,
/// half-turn symmetric, exactly 2 immersions.
CurveSet fig6();

/// Fig. 7: two components, each a thick C-shaped band around one half of an egg-shaped hole;
/// their ends overlap (regions of winding 2), so the hole is bounded by both components and is
/// not the inside of either. 4 crossings, 1 immersion (two overlapping disks).
CurveSet fig7();

/// Fig. 8 (2D): a curve that goes around twice (turning number 2, windings 0..2, one crossing):
/// every winding number is >= 0, yet it bounds no immersed surface. 0 immersions (exit 3).
CurveSet fig8();

/// Fig. 9 / Fig. 11: 4 cells, 8 patches, 4 arcs with the caption's B-patch lists (up to
/// renumbering): a diamond of winding 2 with two lenses below, an arch above and a clockwise
/// kink at the diamond's top corner, where the arch cell self-touches. 1 immersion.
CurveSet fig9();

/// Fig. 12 top: an immersed disk with cells of winding 1, 2 and 3 (a band whose two ends curl
/// over its middle, half-turn symmetric): 6 crossings, 1 immersion, a simple immersion.
CurveSet fig12_simple();

/// Fig. 12 bottom: the boundary of an annulus that winds twice around a hole: two components,
/// each going around twice (outer counter-clockwise, inner clockwise), 2 crossings, 3 cells;
/// the ring-shaped cell of winding 2 is self-connecting, so no simple immersion exists.
CurveSet fig12_ring();

/// Fig. 15 (bottom right) / Fig. 16: three nested Seifert circles with a clockwise kink in the
/// winding-2 annulus joined to the innermost circle (Rule 6 in its three-patch form: a kink
/// patch at two junctions of one arc, all four wedges in cells), a second kink in the outer
/// annulus (an arc with an empty wedge, where Rule 6 does not apply) and one four-patch arc.
/// 4 crossings, 4 cells, 1 immersion.
CurveSet fig15();

// ---- known answers ---------------------------------------------------------------------------

/// A convex polygon with `vertices` >= 3 vertices (a regular polygon rounded to integers):
/// 1 immersion.
CurveSet convex_polygon(int vertices);

/// A figure-eight (lemniscate, one crossing): windings +1 and -1, turning number 0; an
/// inversion, 0 immersions.
CurveSet figure_eight(int samples = 32);

/// The limaçon r = 1 + 2 cos(theta) with its inner loop (one crossing, windings 0..2, turning
/// number 2): 0 immersions. @param samples vertices (>= 12).
CurveSet limacon(int samples = 48);

/// A band that curls once over itself: turning number 1, 2 crossings, a region of winding 2
/// and a bounded hole of winding 0; its winding-1 cell self-touches at both crossings.
/// 1 immersion. Same as spiral(1).
CurveSet curl();

/// A band coiled `turns` >= 1 times over itself around a hole (every turn overlaps all the others
/// near the start): 2 * turns crossings, windings up to turns + 1, turning number 1, a bounded
/// hole of winding 0. 1 immersion (checked up to 20 turns). Generic up to 100 turns.
CurveSet spiral(int turns);

/// The rotationally symmetric Milnor-type doodle with `lobes` = K >= 1: K + 1 concentric
/// counter-clockwise Seifert circles, consecutive ones joined by K crossings each, and K small
/// clockwise kinks in the second-innermost annulus joined to the innermost circle. K(K + 1)
/// crossings, windings 0..K+1, turning number 1, K-fold symmetric (exactly so for K = 1, 2, 4
/// up to integer rounding). The immersions are counted by the Catalan numbers: K = 1, ..., 7
/// give 1, 2, 5, 14, 42, 132, 429 (checked with the search; K = 2 also by brute force).
/// Generic for 1 <= K <= 12 (the grid gets finer for K > 6).
CurveSet doodle(int lobes);

/// `count` >= 1 copies of doodle(lobes) in a row, consecutive outer circles joined by a thin
/// band (no crossing): one curve, count * K(K + 1) crossings, Catalan(K)^count immersions
/// (2^count for the default K = 2).
CurveSet doodle_chain(int count, int lobes = 2);

// ---- random inputs (seeded) ------------------------------------------------------------------

/// A random polygon: `vertices` >= 3 points drawn uniformly from a disk of radius 2^20 (integer
/// coordinates), in random order. Usually self-intersecting (Theta(N^2) crossings) and often an
/// inversion. Generic: if a draw is degenerate, the next draw of the same stream is used.
CurveSet random_polygon(int vertices, std::uint64_t seed);

/// `components` random star-shaped counter-clockwise polygons with `vertices` vertices each,
/// with centres close enough that neighbours overlap: every winding number is >= 0 and the
/// disjoint disks are an immersion (so at least one exists). Generic as above.
CurveSet random_multi(int components, int vertices, std::uint64_t seed);

/// A pile of `count` >= 1 counter-clockwise circles (regular `samples`-gons, samples >= 8) of
/// radius 2^18 whose centres are drawn uniformly from a square of side 0.8 radius, each with a
/// random phase: every two circles overlap, so winding numbers reach about `count` (issue 19).
/// Immersible by construction (the disjoint union of the disks): at least 1 immersion.
/// Generic as random_polygon.
CurveSet circles_pile(int count, std::uint64_t seed, int samples = 32);

// ---- exact genericity check (CGAL-free) -----------------------------------------------------

struct GenericityReport {
  std::size_t crossings = 0;  ///< proper crossings (segment pairs crossing in their interiors)
  bool generic = true;
  std::string problem;  ///< the first defect found, when not generic
};

/// Exact test of the paper's non-degeneracy on the raw segments: no zero-length segment, no
/// collinear overlap, no vertex on another segment (including coinciding vertices), no point
/// where three segments cross. Exact for any double coordinates (integers take a fast path).
GenericityReport check_generic(const CurveSet& curves);

/// Turning number (total signed turning / 2 pi) of a closed polygon without zero-length
/// segments, computed exactly from the quadrant crossings of the edge directions.
int turning_number(const Curve& curve);

}  // namespace imm::dim2
