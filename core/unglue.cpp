// Duplicate-and-connect driver: see core/unglue.h.
#include "core/unglue.h"

#include <algorithm>
#include <limits>
#include <string>

#include "core/diagnostics.h"
#include "core/union_find.h"

namespace imm {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// Position of background vertex v in an element, or -1.
template <std::size_t N>
int local_index(const std::array<std::int32_t, N>& element, std::int32_t v) {
  for (std::size_t k = 0; k < N; ++k)
    if (element[k] == v) return static_cast<int>(k);
  return -1;
}

}  // namespace

template <int D>
UnglueResult<D> unglue(const UnglueInput<D>& input) {
  constexpr int kArity = D + 1;
  const std::size_t element_count = input.elements.size();
  const std::size_t atom_count = input.atoms.size();
  IMM_ASSERT(atom_count < kNone, "too many atoms");

  // 1. Element copies: union-find over atoms, joined by the fusions.
  UnionFind atoms(atom_count);
  for (const auto& [a, b] : input.fusions) {
    IMM_ASSERT(a < atom_count && b < atom_count, "fusion atom out of range");
    IMM_ASSERT(input.atoms[a].element == input.atoms[b].element,
               "fusion joins atoms of two elements " + std::to_string(input.atoms[a].element) +
                   " and " + std::to_string(input.atoms[b].element));
    atoms.unite(a, b);
  }

  // Atoms in (element, index) order: a counting sort keeps the output deterministic and linear.
  std::vector<std::uint32_t> element_start(element_count + 1, 0);
  for (const UnglueAtom& atom : input.atoms) {
    IMM_ASSERT(atom.element < element_count, "atom element out of range");
    ++element_start[atom.element + 1];
  }
  for (std::size_t e = 0; e < element_count; ++e) element_start[e + 1] += element_start[e];
  std::vector<std::uint32_t> order(atom_count);
  {
    std::vector<std::uint32_t> next(element_start.begin(), element_start.end() - 1);
    for (std::uint32_t a = 0; a < atom_count; ++a) order[next[input.atoms[a].element]++] = a;
  }

  UnglueResult<D> out;
  out.atom_copy.assign(atom_count, kNone);
  std::vector<std::uint32_t> root_copy(atom_count, kNone);
  for (std::uint32_t a : order) {
    const std::uint32_t root = atoms.find(a);
    if (root_copy[root] == kNone) {
      root_copy[root] = static_cast<std::uint32_t>(out.copy_element.size());
      out.copy_element.push_back(input.atoms[a].element);
      out.copy_node.push_back(input.atoms[a].node);
    }
    const std::uint32_t copy = root_copy[root];
    out.atom_copy[a] = copy;
    out.copy_node[copy] = std::min(out.copy_node[copy], input.atoms[a].node);
  }
  const std::size_t copy_count = out.copy_element.size();
  IMM_ASSERT(copy_count * kArity < kNone, "too many element copies");

  // 2. Vertex copies: D+1 fresh ones per element copy, merged across connected faces.
  UnionFind vertices(copy_count * kArity);
  for (const UnglueAdjacency<D>& adjacency : input.adjacencies) {
    IMM_ASSERT(adjacency.first < atom_count && adjacency.second < atom_count,
               "adjacency atom out of range");
    const std::uint32_t element_a = input.atoms[adjacency.first].element;
    const std::uint32_t element_b = input.atoms[adjacency.second].element;
    IMM_ASSERT(element_a != element_b, "adjacency inside one element");
    const std::uint32_t copy_a = out.atom_copy[adjacency.first];
    const std::uint32_t copy_b = out.atom_copy[adjacency.second];
    for (std::int32_t v : adjacency.face) {
      const int ia = local_index(input.elements[element_a], v);
      const int ib = local_index(input.elements[element_b], v);
      IMM_ASSERT(ia >= 0 && ib >= 0, "adjacency face vertex " + std::to_string(v) +
                                         " is not a vertex of both elements");
      vertices.unite(copy_a * kArity + ia, copy_b * kArity + ib);
    }
  }

  // 3. Compact numbering, in order of first use by the copies.
  std::vector<std::int32_t> class_id(copy_count * kArity, -1);
  out.copies.resize(copy_count);
  for (std::uint32_t c = 0; c < copy_count; ++c) {
    const auto& element = input.elements[out.copy_element[c]];
    for (int k = 0; k < kArity; ++k) {
      const std::uint32_t root = vertices.find(c * kArity + k);
      if (class_id[root] < 0) {
        class_id[root] = static_cast<std::int32_t>(out.vertex_source.size());
        out.vertex_source.push_back(element[k]);
      }
      IMM_ASSERT(out.vertex_source[class_id[root]] == element[k],
                 "merged vertex copies of two different background vertices");
      out.copies[c][k] = class_id[root];
    }
  }
  return out;
}

template UnglueResult<2> unglue<2>(const UnglueInput<2>&);
template UnglueResult<3> unglue<3>(const UnglueInput<3>&);

template <int D>
AtomExpansion<D>::AtomExpansion(const CellComplex<D>& complex, const Immersion& immersion,
                                const std::vector<std::uint32_t>& first, const std::vector<RegionId>& region,
                                std::vector<std::array<std::int32_t, D + 1>> elements, unsigned threads)
    : complex_(complex), immersion_(immersion), region_(region), edges_across_(complex.patch_count()) {
  input_.elements = std::move(elements);
  IMM_ASSERT(first.size() == input_.elements.size() + 1 && first.back() == region.size(),
             "local regions do not match the elements");
  atom_first_.assign(region.size(), kNoAtom);
  const NodeLayout& layout = immersion.layout;
  // Element by element, in element order: each element's atoms counted, then written at their
  // offsets (the same atoms for every thread count).
  std::vector<UnglueAtom>& atoms = input_.atoms;
  parallel_ordered_append(
      threads, first.size() - 1,
      [&](std::size_t e) {
        std::size_t n = 0;
        for (std::uint32_t lr = first[e]; lr < first[e + 1]; ++lr) n += connect_count(lr);
        return n;
      },
      [&](std::size_t total) {
        IMM_ASSERT(total < kNoAtom, "too many atoms");
        atoms.resize(total);
      },
      [&](std::size_t e, std::size_t at) {
        for (std::uint32_t lr = first[e]; lr < first[e + 1]; ++lr) {
          const CellId cell = complex.cell_of(region[lr]);
          if (!cell.is_valid()) continue;
          atom_first_[lr] = static_cast<std::uint32_t>(at);
          const auto index_in_element = static_cast<std::int32_t>(lr - first[e]);
          for (int k = 0; k < complex.winding_number(cell); ++k)
            atoms[at++] = {static_cast<std::uint32_t>(e), layout.node(cell, k), index_in_element};
        }
      });
  for (const ImmersionEdge& edge : immersion.edges) edges_across_[edge.patch].push_back(edge);
}

template <int D>
std::uint32_t AtomExpansion<D>::atom(std::uint32_t lr, NodeId node) const {
  const NodeLayout& layout = immersion_.layout;
  IMM_ASSERT(atom_first_[lr] != kNoAtom && layout.cell(node) == complex_.cell_of(region_[lr]),
             "graph node of another cell than the local region's");
  return atom_first_[lr] + static_cast<std::uint32_t>(layout.copy(node));
}

template <int D>
void AtomExpansion<D>::fuse(std::uint32_t inner, std::uint32_t outer, PatchId patch) {
  for (const ImmersionEdge& e : edges_across_[patch]) input_.fusions.emplace_back(atom(inner, e.inner), atom(outer, e.outer));
}

template <int D>
void AtomExpansion<D>::connect(std::uint32_t first, std::uint32_t second, const std::array<std::int32_t, D>& face) {
  const CellId cell = complex_.cell_of(region_[first]);
  if (!cell.is_valid()) return;
  for (int k = 0; k < complex_.winding_number(cell); ++k)
    input_.adjacencies.push_back({atom_first_[first] + static_cast<std::uint32_t>(k),
                                  atom_first_[second] + static_cast<std::uint32_t>(k), face});
}

template <int D>
void AtomExpansion<D>::connect_across(std::uint32_t inner, std::uint32_t outer, PatchId patch,
                                      const std::array<std::int32_t, D>& face) {
  for (const ImmersionEdge& e : edges_across_[patch])
    input_.adjacencies.push_back({atom(inner, e.inner), atom(outer, e.outer), face});
}

template class AtomExpansion<2>;
template class AtomExpansion<3>;

}  // namespace imm
