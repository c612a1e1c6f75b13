// Duplicate-and-connect of background elements (paper §7 and §7.1.2; Teran et al. 2005, §6).
//
// The dimension-specific meshing code (dim2/, dim3/) cuts every background element (triangle or
// tetrahedron) by the input and reports what it found as three lists:
//  - atoms: one per (element, graph node, local region of the element lying in that node's cell).
//    A cell c with winding number w(c) gives w(c) atoms per local region (one per node);
//  - fusions: two atoms of the same element glued through an immersion-graph edge across a piece
//    of a patch inside the element (paper §7: "fuse two identical tets from tet meshes of a and b
//    if they both embed the same triangle of p");
//  - adjacencies: two atoms of two elements sharing a face whose parts of that face touch along a
//    positive measure and that the immersion connects there (paper §7.1.2).
// This driver then
//  1. groups the atoms of each element into element copies: the classes of the union-find over
//     the fusions (atoms never merge across elements here);
//  2. gives every copy its own D+1 vertex copies and, for every adjacency, merges the D vertex
//     pairs of the shared face (union-find over vertex copies, Teran et al. 2005 §6);
//  3. numbers the merged vertex classes compactly.
// Nothing here knows the dimension beyond the arity D+1 of an element: the same code serves
// triangles and tetrahedra.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/cell_complex.h"
#include "core/huge_pages.h"
#include "core/ids.h"
#include "core/immersion_graph.h"
#include "core/parallel.h"
#include "core/union_find.h"

namespace imm {

/// How the local regions of the background elements are computed: the paper's exact clipping
/// (§7.1, the default) or the CSG baseline it compares with (Sifakis et al. 2007; Table 2), exact
/// booleans of each element with the regions. Both give the same duplication.
enum class MeshMethod { Clip, Csg };

/// A local region of one background element as seen by one immersion-graph node.
struct UnglueAtom {
  std::uint32_t element = 0;     ///< background element index
  NodeId node;                   ///< the graph node this copy of the local region belongs to
  std::int32_t local_region = 0; ///< the caller's id of the local region within the element
};

/// Two atoms of two elements that share a face and are connected across it. The face is not
/// stored: it is the D vertices the two elements share (8 bytes an adjacency instead of
/// 8 + 4 D, on one of the largest arrays of meshing at scale; BENCHMARKS.md, issue 17).
/// Trivially default-constructible (no member initialisers): the driver's list of them grows
/// without a serial zeroing pass (DefaultInitAllocator), every entry written on all threads.
template <int D>
struct UnglueAdjacency {
  std::uint32_t first;   ///< atom index
  std::uint32_t second;  ///< atom index, in another element sharing a face (D vertices) with first's
};
static_assert(std::is_trivially_default_constructible_v<UnglueAdjacency<2>> &&
                  std::is_trivially_default_constructible_v<UnglueAdjacency<3>>,
              "UnglueInput::adjacencies relies on entries left unwritten until the workers fill them");

/// The input of unglue(): the background mesh and what the element cutting found.
template <int D>
struct UnglueInput {
  /// Background vertex ids of each element (D+1 each). The output keeps this local order.
  std::vector<std::array<std::int32_t, D + 1>> elements;
  std::vector<UnglueAtom> atoms;
  /// Pairs of atom indices in the same element that belong to the same element copy.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> fusions;
  std::vector<UnglueAdjacency<D>, DefaultInitAllocator<UnglueAdjacency<D>>> adjacencies;
};

/// The unglued mesh: element copies over merged vertex copies.
template <int D>
struct UnglueResult {
  /// Output vertex ids of each copy, in the local order of its background element.
  std::vector<std::array<std::int32_t, D + 1>> copies;
  /// Background element of each copy. Copies are sorted by element, and the copies of one element
  /// by the smallest atom index they contain (deterministic for a given input).
  std::vector<std::uint32_t> copy_element;
  /// Reference node of each copy: the smallest node id among its atoms. A copy fused across
  /// graph edges holds several nodes (all glued to each other inside the element); the smallest
  /// one names it in outputs (Medit reference numbers).
  std::vector<NodeId> copy_node;
  /// The copy each atom ended in (indexed like UnglueInput::atoms).
  std::vector<std::uint32_t> atom_copy;
  /// Background vertex of each output vertex.
  std::vector<std::int32_t> vertex_source;
};

/// Duplicates elements per union-find class of atoms and connects the copies.
/// @pre every fusion joins two atoms of one element; every adjacency joins atoms of two elements
///      sharing exactly D vertices, its face (checked: InvariantError otherwise).
/// @return copies over compacted vertex ids; elements without atoms have no copy. The same for
///         every `threads` (the unions run concurrently, the numbering is by smallest member).
/// Paper: §7, §7.1.2; Teran et al. 2005, §6.
template <int D>
UnglueResult<D> unglue(const UnglueInput<D>& input, unsigned threads = 1);

extern template UnglueResult<2> unglue<2>(const UnglueInput<2>&, unsigned);
extern template UnglueResult<3> unglue<3>(const UnglueInput<3>&, unsigned);

/// Builds the UnglueInput of one immersion from the local regions the element cutting found
/// (dim2/virtual_triangles.cpp, dim3/virtual_tets.cpp): every local region lying in a cell c
/// becomes w(c) atoms, one per graph node of c (paper §7: "assign to each immersion graph node
/// that is a copy of c a unique copy of T_c"); the element cutting's fusions and adjacencies
/// become atom pairs through the immersion graph's edges.
template <int D>
class AtomExpansion {
 public:
  static constexpr std::uint32_t kNoAtom = 0xffffffffu;

  /// @param first     local regions of element e are first[e] .. first[e+1]-1
  /// @param region    the region of each local region
  /// @param elements  the background elements (D+1 vertex ids each)
  /// @param threads   threads for the expansion (the atoms are the same for every count)
  AtomExpansion(const CellComplex<D>& complex, const Immersion& immersion, const std::vector<std::uint32_t>& first,
                const std::vector<RegionId>& region, std::vector<std::array<std::int32_t, D + 1>> elements,
                unsigned threads = 1);

  /// Local regions `inner` and `outer` of one element lie on the two sides of a piece of `patch`
  /// inside it: every graph edge across the patch glues their atoms (one element copy).
  void fuse(std::uint32_t inner, std::uint32_t outer, PatchId patch);
  /// Local regions of two elements meet across their shared face, free of the input (one
  /// region): the copies of each node are connected.
  void connect(std::uint32_t first, std::uint32_t second);
  /// Local regions of two elements meet across their shared face along a piece of `patch` (the
  /// input runs in the face; `inner` on the patch's inner side): connected through the graph
  /// edges across it.
  void connect_across(std::uint32_t inner, std::uint32_t outer, PatchId patch);

  /// The atom of local region lr for graph node `node` (a node of the region's cell).
  [[nodiscard]] std::uint32_t atom(std::uint32_t lr, NodeId node) const;
  /// The first atom of a local region, or kNoAtom when it lies in no cell.
  [[nodiscard]] std::uint32_t first_atom(std::uint32_t lr) const { return atom_first_[lr]; }
  [[nodiscard]] const UnglueInput<D>& input() const { return input_; }

  /// Every fusion of `fusions` (fuse(f.inner, f.outer, f.patch)), then every adjacency of
  /// `adjacencies` (connect_across(a.first, a.second, a.patch) when a.patch is valid, else
  /// connect(a.first, a.second)), in order: the lists these calls would make one by one, built on
  /// `threads` threads (each item counted, then written at its offset).
  /// Fusion and Adjacency: LocalRegions<D>::Fusion and ::Adjacency (core/local_regions.h).
  template <class Fusion, class Adjacency>
  void glue(const std::vector<Fusion>& fusions, const std::vector<Adjacency>& adjacencies, unsigned threads);

 private:
  /// How many adjacencies connect() adds for local region lr: one per node of its cell.
  [[nodiscard]] std::size_t connect_count(std::uint32_t lr) const {
    const CellId cell = complex_.cell_of(region_[lr]);
    return cell.is_valid() ? static_cast<std::size_t>(complex_.winding_number(cell)) : 0;
  }

  const CellComplex<D>& complex_;
  const Immersion& immersion_;
  const std::vector<RegionId>& region_;
  IdMap<PatchId, std::vector<ImmersionEdge>> edges_across_;
  std::vector<std::uint32_t> atom_first_;
  UnglueInput<D> input_;
};

template <int D>
template <class Fusion, class Adjacency>
void AtomExpansion<D>::glue(const std::vector<Fusion>& fusions, const std::vector<Adjacency>& adjacencies,
                            unsigned threads) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& fused = input_.fusions;
  const std::size_t fused_before = fused.size();
  parallel_ordered_append(
      threads, fusions.size(), [&](std::size_t i) { return edges_across_[fusions[i].patch].size(); },
      [&](std::size_t total) { resize_advised(fused, fused_before + total); },
      [&](std::size_t i, std::size_t at) {
        const Fusion& f = fusions[i];
        for (const ImmersionEdge& e : edges_across_[f.patch])
          fused[fused_before + at++] = {atom(f.inner, e.inner), atom(f.outer, e.outer)};
      });
  auto& connected = input_.adjacencies;
  const std::size_t connected_before = connected.size();
  parallel_ordered_append(
      threads, adjacencies.size(),
      [&](std::size_t i) {
        const Adjacency& a = adjacencies[i];
        return a.patch.is_valid() ? edges_across_[a.patch].size() : connect_count(a.first);
      },
      [&](std::size_t total) { resize_advised(connected, connected_before + total); },
      [&](std::size_t i, std::size_t at) {
        const Adjacency& a = adjacencies[i];
        if (a.patch.is_valid()) {
          for (const ImmersionEdge& e : edges_across_[a.patch])
            connected[connected_before + at++] = {atom(a.first, e.inner), atom(a.second, e.outer)};
        } else {
          const std::size_t n = connect_count(a.first);
          for (std::size_t k = 0; k < n; ++k)
            connected[connected_before + at++] = {atom_first_[a.first] + static_cast<std::uint32_t>(k),
                                                  atom_first_[a.second] + static_cast<std::uint32_t>(k)};
        }
      });
}

extern template class AtomExpansion<2>;
extern template class AtomExpansion<3>;

}  // namespace imm
