// An independent checker for immersion graphs (DESIGN §4 invariant 3).
//
// It deliberately shares no code with core/immersion_rules.h or the search: it is written from
// the local-manifold characterisation behind paper Theorem 5 (§5.3), not from Rules 1–7.
// Glue w(c) copies of every cell along the graph's edges; the result is a manifold with boundary
// exactly the input iff
//  (a) every cell c has w(c) copies (Theorem 1);
//  (b) at every point of a patch q, the copies of the two adjacent cells pair up into sheets:
//      exactly one copy of the inner cell has q on its boundary (owns it), every other copy of the
//      inner cell is glued across q to exactly one copy of the outer cell, every copy of the outer
//      cell is glued to exactly one copy of the inner cell, and nothing else touches q;
//  (c) around every arc, the local pieces (wedge k, copy x) glued across the junctions form only
//      full disks — a cycle through the four wedges going once around the arc — or half-disks —
//      a path over two consecutive wedges k, k+1 whose free ends are the opposite junctions k
//      and k+2 (one sheet), both owned. Anything else (one wedge with both sides owned, longer
//      paths, cycles going around more than once, a free end without an owner) is not a manifold
//      neighbourhood of the arc with the input as boundary.
#pragma once

#include <string>
#include <vector>

#include "core/cell_complex.h"
#include "core/immersion_graph.h"

namespace imm::test_support {

/// @return human-readable violations of (a)–(c); empty when the immersion is valid.
template <int D>
std::vector<std::string> check_immersion(const CellComplex<D>& complex, const Immersion& immersion);

extern template std::vector<std::string> check_immersion<2>(const CellComplex<2>&, const Immersion&);
extern template std::vector<std::string> check_immersion<3>(const CellComplex<3>&, const Immersion&);

/// All violations joined by newlines (for test failure messages).
std::string join_violations(const std::vector<std::string>& violations);

}  // namespace imm::test_support
