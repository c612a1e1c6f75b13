// Hand-built cell complexes for the core tests: a plain description (regions, patches, arcs) that
// builds a CellComplex<D> for any D, the paper's small examples worked out by hand, and the
// metamorphic transformations the invariants need (relabelling, disjoint union, enclosing).
//
// Conventions are those of core/cell_complex.h: region 0 is the unbounded region; a patch lists
// its negative (inner, winding w + 1) and positive (outer, winding w) side; an arc lists its four
// junction patches in cyclic order and the region of wedge k, between junctions k and k + 1.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/cell_complex.h"

namespace imm::test_support {

struct ComplexSpec {
  struct Region {
    int winding = 0;
    bool simply_connected = true;
  };
  struct Patch {
    int negative = 0;  ///< region on the inner side (winding w + 1)
    int positive = 0;  ///< region on the outer side (winding w)
  };
  struct Arc {
    std::array<int, 4> patch{};
    std::array<int, 4> wedge{};
  };
  std::string name;
  std::vector<Region> regions;  ///< regions[0] is the unbounded region (winding 0)
  std::vector<Patch> patches;
  std::vector<Arc> arcs;
};

/// Builds and finalizes the complex. Every region gets measure 1 (0 for the unbounded one).
template <int D>
CellComplex<D> build(const ComplexSpec& spec);

extern template CellComplex<2> build<2>(const ComplexSpec&);
extern template CellComplex<3> build<3>(const ComplexSpec&);

// ---- transformations ------------------------------------------------------------------------

/// The same complex with regions (except region 0), patches and arcs permuted, and every arc's
/// junction cycle rotated and possibly reversed, all from a seeded generator.
ComplexSpec shuffled(const ComplexSpec& spec, std::uint64_t seed);

/// Two complexes side by side (their unbounded regions merged).
ComplexSpec disjoint_union(const ComplexSpec& a, const ComplexSpec& b);

/// The complex inside a large counter-clockwise circle: every winding number grows by one, the old
/// unbounded region becomes a bounded cell (not simply connected) and one patch is added.
ComplexSpec enclosed(const ComplexSpec& spec);

// ---- named examples (each documented with its expected immersion count) -------------------

/// A counter-clockwise circle: one cell, one patch, no arc. 1 immersion.
ComplexSpec circle();
/// Two nested counter-clockwise circles: a ring (w 1) and a disk (w 2). 1 immersion (two disks).
ComplexSpec nested_circles();
/// Circles outer CCW, middle CCW, inner CW: ring A (w 1), ring B (w 2), disk C (w 1).
/// 2 immersions: {disk + annulus} in two ways.
ComplexSpec nested_annulus_choice();
/// A limaçon with an inner loop (turning number 2): 0 immersions (Rule 5 then Rule 7).
ComplexSpec limacon();
/// Fig. 12 bottom: an annulus wrapped twice; the ring cell R (w 2) is not simply connected.
/// No simple immersion: SelfConnectingCell.
ComplexSpec double_limacon_ring();
/// A strip bent into a spiral whose ends overlap (turning number 1, one region of w 2, two arcs).
/// 1 immersion.
ComplexSpec band();
/// Paper Fig. 9: 4 cells, 8 patches, 4 arcs, wedges derived from the caption.
ComplexSpec fig9();

/// A random abstract complex (not necessarily planar) that satisfies every construction
/// precondition: windings drop by one across patches and every arc has the winding pattern of two
/// crossing sheets. Patches may repeat at adjacent junctions and regions at several wedges.
ComplexSpec random_complex(std::uint64_t seed, int max_winding, int arcs);

/// A random abstract complex like random_complex whose arcs are all *enclosed*: each has the
/// wedge winding numbers (w, w + 1, w + 2, w + 1) with w = 1 or 2 (winding numbers up to 4), so
/// all four wedges lie in cells and Rule 6 applies at every arc. Where w = 2 every wedge's cell has
/// two copies or more, so a wrong graph can have local sheets going around the arc twice, which
/// only Rule 6 forbids (with w = 1 the single copy of the lowest wedge prevents it). random_complex
/// rarely has such arcs within a brute-forceable size.
ComplexSpec random_enclosed_complex(std::uint64_t seed, int arcs);

}  // namespace imm::test_support
