// Procedural 3D inputs (`immerse generate` for surfaces): the paper's 3D shapes, embedded
// controls, shapes with known answers and seeded random families (issue 3, item 5).
//
// CGAL-free header. The registry of these shapes by name is dim3/generator_registry.cpp.
// Every output is a closed, manifold, consistently and outwardly oriented triangle mesh without
// degenerate triangles (dim3/surface.h: the normal (v1 - v0) x (v2 - v0) points out), possibly
// of several components (paper §6.2: a union of closed components is one input). Coordinates
// are doubles; the generators of intersecting shapes give each component a small rigid motion
// with "odd" angles and stagger the rings' sample angles with an irrational jitter, so no
// vertex lies exactly on another sheet, no two edges meet exactly and no two triangles are
// coplanar where sheets meet: the outputs are GENERIC in the paper's sense (§3). Fixed shapes
// are checked by tests/dim3/generators3_test.cpp with `check_generic_surface` (exact
// predicates); seeded random shapes are checked exactly on every call and re-drawn from the
// same stream until generic.
//
// Building blocks: the sweeps of dim3/sweeps.h (rings around a centreline, closed into a
// torus or capped; a capped or closed sweep with `rings` rings has 2 * sides * rings triangles).
// A tube of radius r around a centreline with curvature at most k bounds an immersed solid
// (a ball when capped, a solid torus when closed) whenever r * k < 1: the map
// (s, disk) -> centreline(s) + disk is then locally injective. This is how the shapes below
// are known to be immersible.
//
// Expected answers. `regions` counts every region including the unbounded outside one, `cells`
// the regions with non-zero winding number, `arcs` geometric arcs (intersection curves between
// triple points, or closed loops), each once: the paper's Table 1 counts each arc once per
// sheet (twice) and its "cells" column includes the outside region. Where the counts follow
// from the construction they are stated per generator below; the tests hold them
// (tests/support/expected_surface_counts.h) and check them against the exact cell complex
// (dim3/complex3.h) and the search.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/generator_registry.h"
#include "dim3/surface.h"
#include "dim3/surface_genericity.h"

namespace imm::dim3 {

// ---- the registry (`immerse generate --list`; core/generator_registry.h) -----------------------

struct SurfaceGenerateResult {
  Surface surface;
  std::string error;  ///< unknown name, bad parameter count or range
  [[nodiscard]] bool ok() const { return error.empty(); }
};

/// Runs a surface generator by name. `arguments` are the parameters in order, either plain
/// integers ("3") or "name=value"; missing ones take their defaults. Never throws for bad
/// arguments (they go into `error`).
SurfaceGenerateResult generate_surface(std::string_view name,
                                       const std::vector<std::string>& arguments);

/// Every surface generator by name, in the order `--list` prints them
/// (dim3/generator_registry.cpp): find(name), infos(), summaries() for the list.
const GeneratorRegistry<Surface>& surface_registry();

// ---- embedded controls -------------------------------------------------------------------------

/// A UV sphere of radius 1: `n` >= 3 latitude bands, 2n vertices per ring, two poles;
/// 4 n (n - 1) triangles. 2 regions, 1 cell, 1 patch, 0 arcs, 1 immersion.
Surface sphere(int n);

/// A local fold (issue 16): a bipyramid over a zig-zag hexagon (ring vertices 0-5, apexes 6 on
/// top and 7 below, 12 triangles) whose top vertex is pulled `percent` % of the way from above
/// the ring's centre to beyond ring vertices 3 and 4; from about 70 % on the triangles (3, 4, 6)
/// and (5, 0, 6) of its star cross beyond it (a local fold at vertex 6, exit 3).
Surface folded_bipyramid(int percent);

/// A torus (major radius 1, minor 0.4), `n` >= 6 segments around the axis and n / 2 around
/// the tube: 2 n (n / 2) triangles. 2 regions, 1 cell, 1 patch, 0 arcs, 1 immersion.
Surface torus(int n);

/// Two overlapping spheres (radii 1 and 0.85, centres 1.15 apart), each a sphere(n):
/// 8 n (n - 1) triangles, two components. Regions: outside (0), each sphere minus the other
/// (1 each), the lens (2): 4 regions, 3 cells, 4 patches (each sphere cut in two), 1 arc,
/// 1 immersion (the two balls).
Surface two_spheres(int n);

/// Two overlapping tori (major radius 1, minor 0.4), each revolved from `n` >= 3 profile
/// samples with n ring sides: 4 n^2 triangles (4,096 at n = 32), the input class of the
/// reference implementation's CSG timing. Their tubes cross twice: 5 regions, 4 cells
/// (windings 1, 1, 2, 2), 6 patches, 2 arcs (closed loops), 1 immersion (the two solid tori);
/// the derivation is at the definition (dim3/generators3.cpp).
Surface two_tori(int n);

// ---- the paper's figures -------------------------------------------------------------------

/// A capped tube (radius 0.3, `sides` >= 6 vertices per ring) swept along a prolate trochoid
/// x = u - 2 sin u, y = 1 - 2 cos u, rising slowly in z, u in [-3, 3]: the path makes one
/// loop and passes over itself 0.3 higher (less than the tube diameter), so the tube goes
/// through itself once, like Fig. 1 / Fig. 5 in 3D. Curvature radius >= 0.5 > 0.3: an
/// immersed ball. 6 s + 1 body rings and 3 + 3 cap rings: 2 s (6 s + 7) triangles.
/// 3 regions (0, 1, 2), 2 cells, 3 patches (the outer patch and each strand inside the other),
/// 1 arc (one loop), 1 immersion.
Surface tube_overlap(int sides);

/// Fig. 1: a capped tube (radius 0.3) around a helix of radius 1 and pitch 0.4 with `loops`
/// >= 1 turns: consecutive turns overlap (pitch < diameter), turns two apart do not (0.8 >
/// 0.6). `sides` = s (even, >= 6) vertices per ring, 5 s / 2 rings per turn: 2 s (5 s / 2 *
/// loops + 7) triangles = 5 s^2 loops + 14 s; the paper's 100 loops (200,036 triangles) is
/// helix(100, 20) with 200,280. The winding-2 region is one helical band from the first cap to
/// the last; its boundary is one intersection loop. 3 regions, 2 cells, 3 patches, 1 arc,
/// max winding 2, 1 immersion (Table 1: 3 cells with the outside, 3 patches, 2 arcs).
Surface helix(int loops, int sides = 20);

/// Fig. 13: a closed tube (radius 0.3) whose core winds twice around the z axis,
/// c(t) = ((1 + 0.22 cos(t/2)) cos t, (1 + 0.22 cos(t/2)) sin t, 0.15 sin(t/2)), t in [0, 4 pi]
/// (a (2,1) torus knot, unknotted): the two strands over each angle are 0.3 to 0.44 apart, so
/// the tube overlaps itself all the way round. `n` >= 8 rings per turn (2 n rings), n / 2
/// sides: 4 n (n / 2) triangles. 3 regions: outside, a winding-1 region (one crescent tube
/// going round twice) and a winding-2 ring whose preimage in the solid torus is connected:
/// a SELF-CONNECTING cell (paper §5, Fig. 12/13). 2 cells, 2 patches, 1 arc; no simple
/// immersion until a helper box cuts the ring (paper §6.2, Fig. 17), then 1.
Surface double_loop_torus(int n);

/// Fig. 24: a torus (major 1, minor 0.35; `n` >= 12 segments around the axis, n / 2 around
/// the tube) with vertical capped columns (radius 0.12, about z in [-0.75, 0.75]) through its
/// tube, each a separate component: small = 4 columns, each cutting the torus in two loops
/// (top and bottom); large = 8 such columns plus 4 thinner columns grazing the outer rim (one
/// loop each). Columns have s = max(6, n / 3) sides, 3 body rings and round caps (18 s
/// triangles each): 2 n (n / 2) + 18 s * (4 or 12) triangles.
/// Small: regions 2 + 3 * 4 = 14, cells 13, patches 1 + 5 * 4 = 21, arcs 8.
/// Large: regions 2 + 3 * 8 + 2 * 4 = 34, cells 33, patches 1 + 5 * 8 + 3 * 4 = 53, arcs 20.
/// Max winding 2; 1 immersion (the torus and the columns' solids).
Surface sacht_torus(int n, bool large);

/// Fig. 22: five tori (major 1, minor 0.3) in a pentagon ring, neighbours overlapping, and
/// seven colliding capped cylinders (radius 0.16) whose axes all pass within 0.03 of the
/// centre: five nearly horizontal ones across the whole ring (through tori and their overlaps)
/// and two tilted vertical ones. The centre has winding number 7 (the paper's maximum).
/// `n` >= 8: tori with n segments around their axis and n / 2 around the tube, cylinders with
/// s = max(6, n / 2) sides and b = max(3, 2 n / 3) body rings: 10 n (n / 2) + 14 s (b + 6)
/// triangles. Regions, cells and patches are not derived by hand; at least 1 immersion (the
/// components' solids).
Surface quintuple_torus(int n);

/// Fig. 3: a procedural tree of `branches` >= 1 capped hexagonal cylinders (trunk, then three
/// children per branch, breadth first; each child 0.8 times as long and 0.68 times as thick as
/// its parent, leaving 32-70 degrees off its parent's axis, bent upwards). Each child starts
/// on its parent's axis, so its root is buried in the parent and it pierces the parent's wall
/// in one loop; a candidate that would touch any other branch (capsule distance test with a margin)
/// is re-drawn or skipped, so branches meet only their parents. 120 triangles per branch
/// (6 sides, 4 body rings, 3 + 3 cap rings); the paper's 328k triangles are about tree(2734).
/// With b branches: regions 2b, cells 2b - 1, patches 3b - 2, arcs b - 1, max winding 2
/// (1 for b = 1), 1 immersion. Exactly `branches` components unless the tree runs out of room
/// (never seen: seeds 1-3 reach 200,000 branches, in about 6 s).
Surface tree(int branches, std::uint64_t seed = 1);

/// Fig. 2: a head-like sphere (radius 1, the back of the head a pole) that narrows at the front
/// into a lip (radius 0.15), which curls down and back (bend radius 0.3) and pierces the chin:
/// its rounded tip is buried inside the head. One sweep (an immersed ball), `n` >= 16 sides,
/// n / 2 head rings, n lip rings and 3 tip rings: 2 n (n / 2 + n + 3) triangles.
/// 3 regions (0, 1, 2), 2 cells, 3 patches (the rest, the lip tip inside the head, the chin
/// disk inside the lip), 1 arc, 1 immersion (Table 1 "head": 3, 3, 2 with its conventions).
Surface head(int n);

// ---- Fig. 8: not the boundary of an immersion -----------------------------------------------

/// The limaçon r = 1 + 2 cos(theta) with its inner loop (turning number 2, Fig. 8 in 2D),
/// revolved around an axis 1.2 to its left (which it does not meet): an immersed torus whose
/// winding numbers are all >= 0 (0, 1 and 2 in the revolved inner loop) but which bounds no
/// immersion. `n` >= 12 profile samples, n ring sides: 2 n^2 triangles. 3 regions, 2 cells,
/// 2 patches, 1 arc; 0 immersions (exit 3).
Surface limacon_torus(int n);

/// The figure-eight x = cos t, y = sin t cos t revolved around an axis 1.5 to its left: the
/// outer lobe has winding +1, the inner lobe -1 (an inversion). `n` >= 12 profile samples, n
/// ring sides: 2 n^2 triangles. 3 regions, 2 cells, 2 patches, 1 arc; 0 immersions (exit 3).
Surface figure_eight_torus(int n);

/// A sphere turned partially inside out: a tunnel (radius 0.3) dented into the unit sphere
/// from below runs up the axis and pokes out through the top to z = 1.4, where it is closed by
/// a round cap. One surface of revolution (genus 0). Inside the poked-out tip the winding
/// number is -1 (an inversion). `n` >= 8 sides; 3 tip rings, n / 2 tunnel rings and n sphere
/// rings: 2 n (3 + n / 2 + n) triangles.
/// 3 regions (0, 1, -1), 2 cells, 3 patches, 1 arc; 0 immersions (exit 3).
Surface poke_through(int n);

// ---- nearly self-intersecting, no intersection ---------------------------------------------

/// A comb: a bar (height 2) with `teeth` = t >= 1 teeth (width 1, length 6) separated by gaps
/// of 1/64, extruded to depth 1 from its outline (dyadic coordinates: exact, axis-aligned,
/// no motion applied). 12 t vertices, 24 t - 4 triangles (walls and two triangulated caps;
/// coplanar neighbours only share edges). No intersection: 2 regions, 1 cell, 1 patch, 0 arcs,
/// 1 immersion.
Surface comb(int teeth);

/// The head of `head(n)` whose lip stops short of the chin: the lip's capsule (radius 0.15)
/// stays 0.004 outside the unit sphere, and every triangle lies inside its smooth shape, so
/// the gap survives meshing. Same triangle count as head(n). No intersection: 2 regions,
/// 1 cell, 1 patch, 0 arcs, 1 immersion.
Surface mouth(int n);

// ---- seeded random inputs ---------------------------------------------------------------------

/// `blobs` >= 1 random star-shaped ellipsoids (semi-axes 0.6..1.2, smooth radial noise of at
/// most 15%), randomly rotated and placed in a cube whose side grows like blobs^(1/3), so
/// neighbours overlap: a union of embedded components (at least 1 immersion). `n` >= 4:
/// each blob is a sphere(n) (4 n (n - 1) triangles). Checked generic; redrawn if not.
Surface random_blobs(int blobs, std::uint64_t seed, int n = 10);

/// A solid torus whose core is a randomly perturbed limaçon-like closed curve (one
/// self-crossing, small random lift in z) with a randomly bumped tube: the tube's radius is
/// 0.6 / (maximum core curvature) times at most 1.2, so it is an immersed solid torus (at
/// least 1 immersion); the tube usually passes through itself at the core's crossing.
/// `n` >= 12: 4 n rings of n / 2 sides: 8 n (n / 2) triangles. Checked generic.
Surface perturbed_torus(int n, std::uint64_t seed);

/// Piles of mutually overlapping closed parts (issue 19), seeded, each part with a random
/// rotation: immersible by construction (the disjoint union of the parts' solids), so at least
/// 1 immersion; winding numbers reach about the number of parts.
/// `count` >= 1 spheres of radius 0.5 (unit_sphere(n) scaled: 2n sides, n - 1 rings) whose
/// centres are uniform in a cube of side 0.6: every two overlap.
Surface spheres_pile(int count, std::uint64_t seed, int n = 8);
/// `count` >= 1 tori (major radius 0.5, minor 0.18; n segments around the axis, n / 2 around
/// the tube) with random orientations and centres uniform in a cube of side 0.6.
Surface tori_pile(int count, std::uint64_t seed, int n = 16);
/// helix(loops, 12) (the Fig. 13 tube coiled `loops` >= 1 times, radius 1, pitch 0.4) inside a
/// pile of `count` spheres of radius 0.5 whose centres are uniform in [-1, 1]^2 x [0, 0.4 loops].
Surface helix_in_spheres(int count, std::uint64_t seed, int loops = 2, int n = 6);

}  // namespace imm::dim3
