// The immersion graph of paper §5: winding-number copies ("nodes") of every cell, edges that
// glue two nodes across a B-patch, and the node that owns each patch.
#pragma once

#include <string>
#include <vector>

#include "core/cell_complex.h"

namespace imm {

/// Where the nodes of each cell live: cell c has nodes first(c) .. first(c) + w(c) - 1
/// (Theorem 1 / Algorithm 1: #nodes = winding number).
class NodeLayout {
 public:
  NodeLayout() = default;
  template <int D>
  explicit NodeLayout(const CellComplex<D>& complex) {
    first_.resize(complex.cell_count());
    for (CellId c : ids<CellId>(complex.cell_count())) {
      first_[c] = NodeId(cell_of_.size());
      for (int k = 0; k < complex.winding_number(c); ++k) cell_of_.push_back(c);
    }
  }
  [[nodiscard]] std::size_t node_count() const { return cell_of_.size(); }
  [[nodiscard]] CellId cell(NodeId n) const { return cell_of_[n]; }
  [[nodiscard]] NodeId first(CellId c) const { return first_[c]; }
  /// @return the copy index of a node within its cell, 0 .. w(c) - 1.
  [[nodiscard]] int copy(NodeId n) const { return n.value() - first_[cell_of_[n]].value(); }
  [[nodiscard]] NodeId node(CellId c, int copy) const { return NodeId(first_[c].value() + copy); }

 private:
  IdMap<CellId, NodeId> first_;
  IdMap<NodeId, CellId> cell_of_;
};

/// Two nodes glued across a patch. `inner` is a copy of the patch's inner (negative-side) cell,
/// `outer` a copy of its outer cell.
struct ImmersionEdge {
  NodeId inner;
  NodeId outer;
  PatchId patch;
  auto operator<=>(const ImmersionEdge&) const = default;
};

/// One complete immersion: a graph satisfying Rules 1–7 (paper §5.2).
struct Immersion {
  NodeLayout layout;
  IdMap<PatchId, NodeId> owner;       ///< the node that owns each patch (Rule 7)
  std::vector<ImmersionEdge> edges;   ///< sorted by (inner, outer, patch)

  /// @return the edge of node n across patch p, or nullptr when n owns p / has none.
  [[nodiscard]] const ImmersionEdge* edge_across(NodeId n, PatchId p) const;
  /// @return the node glued to n across p, or an invalid id.
  [[nodiscard]] NodeId partner(NodeId n, PatchId p) const;
  /// Connected components of the graph: one per connected component of the immersed manifold.
  [[nodiscard]] std::vector<std::vector<NodeId>> components() const;
};

/// A canonical form of an immersion, equal for two immersions iff they are isomorphic under a
/// permutation of the copies of each cell (DESIGN §4, invariant 4). Each node has at most one edge
/// per patch, so fixing one node of a connected component fixes the whole relabelling: the form is
/// the lexicographically least breadth-first relabelling over all starting nodes, per component,
/// with the component forms sorted.
template <int D>
std::string canonical_form(const CellComplex<D>& complex, const Immersion& immersion);

extern template std::string canonical_form<2>(const CellComplex<2>&, const Immersion&);
extern template std::string canonical_form<3>(const CellComplex<3>&, const Immersion&);

}  // namespace imm
