#include "core/immersion_graph.h"

#include <algorithm>
#include <numeric>

#include "core/graph_search.h"

namespace imm {

const ImmersionEdge* Immersion::edge_across(NodeId n, PatchId p) const {
  // Edges are sorted by inner node: binary search when n is the inner end, scan otherwise.
  const auto lower = std::lower_bound(edges.begin(), edges.end(), n,
                                      [](const ImmersionEdge& e, NodeId v) { return e.inner < v; });
  for (auto it = lower; it != edges.end() && it->inner == n; ++it) {
    if (it->patch == p) return &*it;
  }
  for (const ImmersionEdge& e : edges) {
    if (e.outer == n && e.patch == p) return &e;
  }
  return nullptr;
}

NodeId Immersion::partner(NodeId n, PatchId p) const {
  const ImmersionEdge* e = edge_across(n, p);
  if (e == nullptr) return NodeId();
  return e->inner == n ? e->outer : e->inner;
}

std::vector<std::vector<NodeId>> Immersion::components() const {
  const std::size_t count = layout.node_count();
  std::vector<std::size_t> parent(count);
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  const auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const ImmersionEdge& e : edges) {
    const std::size_t a = find(e.inner.index()), b = find(e.outer.index());
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  // Roots are the smallest node of their component, so components come out ordered by it.
  std::vector<std::vector<NodeId>> out;
  std::vector<std::size_t> slot(count, count);
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t root = find(n);
    if (slot[root] == count) {
      slot[root] = out.size();
      out.emplace_back();
    }
    out[slot[root]].push_back(NodeId(n));
  }
  return out;
}

const char* to_string(ImmersionStatus status) {
  switch (status) {
    case ImmersionStatus::Immersible: return "immersible";
    case ImmersionStatus::NotImmersible: return "not-immersible";
    case ImmersionStatus::SelfConnectingCell: return "self-connecting-cell";
    case ImmersionStatus::SearchBudgetExhausted: return "search-budget-exhausted";
  }
  return "unknown";
}

}  // namespace imm
