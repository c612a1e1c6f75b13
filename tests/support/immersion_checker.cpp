// Independent immersion checker: see immersion_checker.h. Uses only the public data of the cell
// complex and of the Immersion (layout, owner, edges), never core/immersion_rules.h.
#include "support/immersion_checker.h"

#include <algorithm>
#include <array>
#include <sstream>
#include <utility>

namespace imm::test_support {
namespace {

/// State of one side of a local piece (wedge k, node x) at an arc.
enum class Side { Owned, Linked, Missing, Broken };

struct Piece {
  int wedge;
  NodeId node;
  Side left = Side::Missing, right = Side::Missing;
  int left_piece = -1, right_piece = -1;  ///< neighbouring piece when Linked
};

}  // namespace

template <int D>
std::vector<std::string> check_immersion(const CellComplex<D>& complex, const Immersion& im) {
  std::vector<std::string> out;
  const auto say = [&](auto&&... parts) {
    std::ostringstream os;
    (os << ... << parts);
    out.push_back(os.str());
  };

  // (a) copies per cell.
  const std::size_t node_count = im.layout.node_count();
  std::vector<std::vector<NodeId>> nodes_of(complex.cell_count());
  for (std::size_t i = 0; i < node_count; ++i) {
    const NodeId n(i);
    const CellId c = im.layout.cell(n);
    if (!c.is_valid() || c.index() >= complex.cell_count()) {
      say("node ", n, " belongs to no cell of the complex");
      continue;
    }
    nodes_of[c.index()].push_back(n);
  }
  for (std::size_t c = 0; c < complex.cell_count(); ++c) {
    const int w = complex.winding_number(CellId(c));
    if (static_cast<int>(nodes_of[c].size()) != w) {
      say("cell ", c, " has ", nodes_of[c].size(), " copies but winding number ", w);
    }
  }
  if (im.owner.size() != complex.patch_count()) {
    say("the ownership table has ", im.owner.size(), " entries for ", complex.patch_count(),
        " patches");
    return out;
  }
  const auto cell_of_node = [&](NodeId n) {
    return n.is_valid() && n.index() < node_count ? im.layout.cell(n) : CellId();
  };

  // Partners of every (node, patch), from the raw edge list.
  // partners[n]: (patch, partner) pairs of node n.
  std::vector<std::vector<std::pair<PatchId, NodeId>>> partners(node_count);
  for (const ImmersionEdge& e : im.edges) {
    if (!e.patch.is_valid() || e.patch.index() >= complex.patch_count()) {
      say("an edge crosses patch ", e.patch, ", which does not exist");
      continue;
    }
    const CellId inner = complex.cell_of(complex.sides(e.patch).negative);
    const CellId outer = complex.cell_of(complex.sides(e.patch).positive);
    if (cell_of_node(e.inner) != inner || !outer.is_valid() || cell_of_node(e.outer) != outer) {
      say("edge ", e.inner, " - ", e.outer, " across patch ", e.patch,
          " does not join a copy of its inner cell ", inner, " to a copy of its outer cell ", outer);
      continue;
    }
    partners[e.inner.index()].emplace_back(e.patch, e.outer);
    partners[e.outer.index()].emplace_back(e.patch, e.inner);
  }
  const auto partners_of = [&](NodeId n, PatchId p) {
    std::vector<NodeId> out;
    for (const auto& [q, m] : partners[n.index()]) {
      if (q == p) out.push_back(m);
    }
    return out;
  };

  // (b) sheets along every patch.
  for (std::size_t i = 0; i < complex.patch_count(); ++i) {
    const PatchId p(i);
    const CellId inner = complex.cell_of(complex.sides(p).negative);
    const CellId outer = complex.cell_of(complex.sides(p).positive);
    const NodeId owner = im.owner[p];
    if (!owner.is_valid() || owner.index() >= node_count) {
      say("patch ", p, " has no owner");
    } else if (cell_of_node(owner) != inner) {
      say("patch ", p, " is owned by node ", owner, " of cell ", cell_of_node(owner),
          ", but only a copy of its inner cell ", inner, " can have it on its boundary");
    }
    for (NodeId n : nodes_of[inner.index()]) {
      const std::size_t k = partners_of(n, p).size();
      if (n == owner && k != 0) {
        say("node ", n, " owns patch ", p, " but is also glued across it ", k, " time(s)");
      } else if (n != owner && k != 1) {
        say("node ", n, " (inner side of patch ", p, ") does not own it and is glued across it ", k,
            " times instead of once");
      }
    }
    if (outer.is_valid()) {
      for (NodeId n : nodes_of[outer.index()]) {
        const std::size_t k = partners_of(n, p).size();
        if (k != 1) {
          say("node ", n, " (outer side of patch ", p, ") is glued across it ", k,
              " times instead of once");
        }
      }
    }
  }

  // (c) local pieces around every arc.
  for (std::size_t ai = 0; ai < complex.arc_count(); ++ai) {
    const ArcJunctions& arc = complex.arc(ArcId(ai));
    std::vector<Piece> pieces;
    std::array<std::vector<NodeId>, 4> wedge_nodes;  // piece index = offset[k] + position
    std::array<int, 4> offset{};
    for (int k = 0; k < 4; ++k) {
      offset[k] = static_cast<int>(pieces.size());
      const CellId c = complex.cell_of(arc.wedge[k]);
      if (!c.is_valid()) continue;
      wedge_nodes[k] = nodes_of[c.index()];
      for (NodeId n : wedge_nodes[k]) pieces.push_back(Piece{k, n});
    }
    const auto find_piece = [&](int k, NodeId n) {
      const auto& list = wedge_nodes[k];
      const auto it = std::find(list.begin(), list.end(), n);
      return it == list.end() ? -1 : offset[k] + static_cast<int>(it - list.begin());
    };
    // One side of a piece: the junction patch is owned by the node, or the node is glued to a
    // node of the neighbouring wedge across it.
    const auto side = [&](const Piece& piece, int junction, int neighbour_wedge, int* linked) {
      const PatchId p = arc.patch[junction];
      if (im.owner[p] == piece.node) return Side::Owned;
      const std::vector<NodeId> list = partners_of(piece.node, p);
      if (list.empty()) return Side::Missing;
      if (list.size() > 1) return Side::Broken;
      const int other = find_piece(neighbour_wedge, list.front());
      if (other < 0) return Side::Broken;
      *linked = other;
      return Side::Linked;
    };
    for (Piece& piece : pieces) {
      const int k = piece.wedge;
      piece.left = side(piece, k, (k + 3) % 4, &piece.left_piece);
      piece.right = side(piece, (k + 1) % 4, (k + 1) % 4, &piece.right_piece);
    }
    // Links must be mutual; a one-sided link is broken.
    for (Piece& piece : pieces) {
      if (piece.left == Side::Linked && pieces[piece.left_piece].right_piece != &piece - pieces.data()) {
        piece.left = Side::Broken;
      }
      if (piece.right == Side::Linked && pieces[piece.right_piece].left_piece != &piece - pieces.data()) {
        piece.right = Side::Broken;
      }
    }
    const auto name = [&](int i) {
      std::ostringstream os;
      os << "(wedge " << pieces[i].wedge << ", node " << pieces[i].node << " of cell "
         << im.layout.cell(pieces[i].node) << ")";
      return os.str();
    };
    const auto side_name = [](Side s) {
      switch (s) {
        case Side::Owned: return "owned";
        case Side::Linked: return "glued";
        case Side::Missing: return "neither owned nor glued";
        case Side::Broken: return "glued inconsistently";
      }
      return "?";
    };
    std::vector<char> seen(pieces.size(), 0);
    for (std::size_t start = 0; start < pieces.size(); ++start) {
      if (seen[start]) continue;
      // Walk left to the free end, or once around a cycle.
      int u = static_cast<int>(start);
      bool cycle = false;
      while (pieces[u].left == Side::Linked) {
        u = pieces[u].left_piece;
        if (u == static_cast<int>(start)) {
          cycle = true;
          break;
        }
      }
      std::vector<int> chain;
      int v = u;
      do {
        chain.push_back(v);
        seen[v] = 1;
        if (pieces[v].right != Side::Linked) break;
        v = pieces[v].right_piece;
      } while (v != u);
      std::ostringstream desc;
      for (std::size_t i = 0; i < chain.size(); ++i) desc << (i ? " - " : "") << name(chain[i]);
      if (cycle) {
        if (chain.size() != 4) {
          say("arc ", ai, ": the pieces ", desc.str(), " form a cycle over ", chain.size(),
              " wedges (it winds around the arc ", chain.size() / 4.0, " times, not once)");
        }
        continue;
      }
      const Piece& first = pieces[chain.front()];
      const Piece& last = pieces[chain.back()];
      if (chain.size() != 2 || first.left != Side::Owned || last.right != Side::Owned) {
        say("arc ", ai, ": the pieces ", desc.str(), " form a path over ", chain.size(),
            " wedge(s) whose free ends (junction ", first.wedge, ": ", side_name(first.left),
            "; junction ", (last.wedge + 1) % 4, ": ", side_name(last.right),
            ") are not a half-disk bounded by one sheet");
      }
    }
  }
  return out;
}

template std::vector<std::string> check_immersion<2>(const CellComplex<2>&, const Immersion&);
template std::vector<std::string> check_immersion<3>(const CellComplex<3>&, const Immersion&);

std::string join_violations(const std::vector<std::string>& violations) {
  std::string out;
  for (const std::string& v : violations) out += v + "\n";
  return out;
}

}  // namespace imm::test_support
