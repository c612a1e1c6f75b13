// The combinatorial cell complex of a self-intersecting input (paper §4), shared by 2D and 3D.
//
// dim2/ and dim3/ build it from exact geometry; the immersion search (graph_search.h) reads only
// what is stored here:
//  - regions with their winding numbers and exact measures (area or volume);
//  - cells: regions with a non-zero winding number (§4.1);
//  - patches with the region on each side;
//  - arcs with their four patch junctions in cyclic order and the four wedges between them.
//
// Everything else the paper defines is derived from those facts, never stored twice:
//  - the B-patches of a cell and their agreement (§4.2) come from the patch sides;
//  - topological neighbours at an arc are the patches of opposite junctions (same sheet);
//  - geometric neighbours w.r.t. a cell are the patches of the two junctions bounding a wedge of
//    that cell. A self-touching cell (§4.2.1) occupies two wedges of one arc, and each wedge gives
//    its own pair: this is exactly the paper's disconnection of the two local manifold regions.
//
// Orientation convention: the patch normal points to its *positive* side, and the winding number
// drops by one across a patch in the direction of its normal, so
//     winding(negative side) = winding(positive side) + 1.
// In 2D the normal is the right-hand side of the curve direction (counter-clockwise outer curves
// have winding +1 inside). A B-patch *agrees* with a cell when the normal points out of the cell,
// i.e. when the cell is the patch's negative side.
#pragma once

#include <array>
#include <span>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/dim_traits.h"
#include "core/ids.h"
#include "core/rational.h"

namespace imm {

/// Which side of a patch a region lies on.
struct PatchSides {
  RegionId positive;  ///< the side the normal points to (winding w)
  RegionId negative;  ///< the other side (winding w + 1)

  /// @pre r is one of the two sides.  @return the region across the patch from r.
  [[nodiscard]] RegionId opposite(RegionId r) const { return r == positive ? negative : positive; }
};

/// The neighbourhood of one arc: four patch junctions in cyclic order, with wedge k lying between
/// junction k and junction k+1 (mod 4). Junction k's patch therefore separates wedge k-1 and
/// wedge k, and junctions k and k+2 lie on the same sheet of the input.
/// Paper: §4.2.1 (patch junctions), Fig. 11, Fig. 15.
struct ArcJunctions {
  std::array<PatchId, 4> patch;   ///< patch of junction k (a patch may occur at several junctions)
  std::array<RegionId, 4> wedge;  ///< region of wedge k
};

/// A patch seen from one of the cells it bounds. Paper: §4.2.
struct BPatch {
  PatchId patch;
  bool agrees;  ///< the patch normal points out of the cell (the cell is its negative side)
};

/// Two B-patches of `cell` that are spatially adjacent at `arc`, bounding wedge `wedge`.
/// Paper: §4.2, §4.2.1.
struct GeometricNeighbors {
  CellId cell;
  ArcId arc;
  int wedge;      ///< 0..3: the pair is (junction wedge, junction wedge+1)
  PatchId first;  ///< patch of junction `wedge`
  PatchId second; ///< patch of junction `wedge + 1`
};

/// The cell complex of paper §4. Templated on the dimension for the design card's "one solver";
/// no member depends on D except through DimTraits<D>.
template <int D>
  requires ImmersionDim<DimTraits<D>>
class CellComplex {
 public:
  static constexpr int kDim = D;

  // ---- construction (used by dim2/ and dim3/ builders) -----------------------------------

  /// Adds a region. The first region added must be the unbounded one (winding 0).
  /// @param measure exact area (2D) or volume (3D); 0 for the unbounded region.
  /// @param simply_connected false when the region has a non-trivial fundamental group (a 2D
  ///        face with holes). Only such a cell can be self-connecting (paper §5.1, Fig. 12).
  RegionId add_region(int winding_number, Rational measure, bool simply_connected = true);

  /// Adds a patch separating two regions. @pre winding(negative) == winding(positive) + 1.
  PatchId add_patch(PatchSides sides);

  /// Adds an arc with its four junctions. @pre sides(patch[k]) == {wedge[k-1], wedge[k]}.
  ArcId add_arc(const ArcJunctions& arc);

  /// Derives cells, B-patches and per-patch arcs, and checks every construction precondition.
  /// @throw InvariantError when the builder violated a precondition (a bug, not bad input).
  void finalize();

  // ---- regions and cells ---------------------------------------------------------------

  [[nodiscard]] std::size_t region_count() const { return winding_.size(); }
  [[nodiscard]] int winding_number(RegionId r) const { return winding_[r]; }
  [[nodiscard]] const Rational& measure(RegionId r) const { return measure_[r]; }
  [[nodiscard]] bool is_simply_connected(RegionId r) const { return simply_connected_[r] != 0; }
  [[nodiscard]] bool is_cell(RegionId r) const { return region_cell_[r].is_valid(); }
  /// @return the cell of a region, or an invalid id when the region is not a cell.
  [[nodiscard]] CellId cell_of(RegionId r) const { return region_cell_[r]; }

  [[nodiscard]] std::size_t cell_count() const { return cell_region_.size(); }
  [[nodiscard]] RegionId region_of(CellId c) const { return cell_region_[c]; }
  [[nodiscard]] int winding_number(CellId c) const { return winding_[cell_region_[c]]; }
  [[nodiscard]] int max_winding_number() const;
  /// @return the B-patches of a cell, sorted by patch id. Paper: §4.2.
  [[nodiscard]] std::span<const BPatch> b_patches(CellId c) const { return b_patches_[c]; }

  // ---- patches -----------------------------------------------------------------------------

  [[nodiscard]] std::size_t patch_count() const { return sides_.size(); }
  [[nodiscard]] const PatchSides& sides(PatchId p) const { return sides_[p]; }
  /// The cell on the negative side (always a cell: its winding number is at least 1).
  [[nodiscard]] CellId inner_cell(PatchId p) const { return region_cell_[sides_[p].negative]; }
  /// The cell on the positive side, or an invalid id when that side has winding number 0.
  [[nodiscard]] CellId outer_cell(PatchId p) const { return region_cell_[sides_[p].positive]; }
  /// Arcs at which the patch has a junction (each listed once, sorted).
  [[nodiscard]] std::span<const ArcId> arcs_of(PatchId p) const { return patch_arcs_[p]; }

  // ---- arcs ---------------------------------------------------------------------------------

  [[nodiscard]] std::size_t arc_count() const { return arcs_.size(); }
  [[nodiscard]] const ArcJunctions& arc(ArcId a) const { return arcs_[a]; }

  /// The two pairs of topological neighbours at an arc: (junction 0, 2) and (1, 3). Paper: §4.1.
  [[nodiscard]] std::array<std::array<PatchId, 2>, 2> topological_neighbors(ArcId a) const;
  /// Every geometric-neighbour pair of every cell, one per (arc, wedge) that lies in a cell.
  [[nodiscard]] std::vector<GeometricNeighbors> geometric_neighbors() const;
  /// Arcs at which a cell occupies two wedges (self-touching, §4.2.1).
  [[nodiscard]] std::vector<ArcId> self_touching_arcs(CellId c) const;

 private:
  IdMap<RegionId, int> winding_;
  IdMap<RegionId, Rational> measure_;
  IdMap<RegionId, std::uint8_t> simply_connected_;  // not bool: IdMap wraps std::vector
  IdMap<RegionId, CellId> region_cell_;
  IdMap<CellId, RegionId> cell_region_;
  IdMap<PatchId, PatchSides> sides_;
  IdMap<PatchId, std::vector<ArcId>> patch_arcs_;
  IdMap<ArcId, ArcJunctions> arcs_;
  IdMap<CellId, std::vector<BPatch>> b_patches_;
  bool finalized_ = false;
};

extern template class CellComplex<2>;
extern template class CellComplex<3>;

}  // namespace imm
