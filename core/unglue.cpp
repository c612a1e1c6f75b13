// Duplicate-and-connect driver: see core/unglue.h.
#include "core/unglue.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <string>

#include "core/diagnostics.h"
#include "core/huge_pages.h"
#include "core/parallel.h"
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
UnglueResult<D> unglue(const UnglueInput<D>& input, unsigned threads) {
  constexpr int kArity = D + 1;
  constexpr std::size_t kBlock = 1 << 14;  // items per task of the cheap loops below
  const std::size_t element_count = input.elements.size();
  const std::size_t atom_count = input.atoms.size();
  IMM_ASSERT(atom_count < kNone, "too many atoms");

  // 1. Element copies: union-find over atoms, joined by the fusions.
  MinRootUnionFind atoms(atom_count, threads);
  parallel_blocks(threads, input.fusions.size(), kBlock, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      const auto [a, b] = input.fusions[f];
      IMM_ASSERT(a < atom_count && b < atom_count, "fusion atom out of range");
      IMM_ASSERT(input.atoms[a].element == input.atoms[b].element,
                 "fusion joins atoms of two elements " + std::to_string(input.atoms[a].element) + " and " +
                     std::to_string(input.atoms[b].element));
      atoms.unite(a, b);
    }
  });
  std::unique_ptr<std::uint32_t[]> atom_root = uninitialized_array<std::uint32_t>(atom_count);
  parallel_blocks(threads, atom_count, kBlock, [&](std::size_t begin, std::size_t end) {
    for (std::size_t a = begin; a < end; ++a) {
      IMM_ASSERT(input.atoms[a].element < element_count, "atom element out of range");
      atom_root[a] = atoms.find(static_cast<std::uint32_t>(a));
    }
  });
  atoms.release();

  // Atoms in (element, index) order: a counting sort keeps the output deterministic and linear.
  // The meshers list atoms element by element already: then the order is the identity.
  std::vector<std::uint32_t> order;
  const bool by_element = std::is_sorted(input.atoms.begin(), input.atoms.end(),
                                         [](const UnglueAtom& x, const UnglueAtom& y) { return x.element < y.element; });
  if (!by_element) {
    std::vector<std::uint32_t> element_start(element_count + 1, 0);
    for (const UnglueAtom& atom : input.atoms) ++element_start[atom.element + 1];
    for (std::size_t e = 0; e < element_count; ++e) element_start[e + 1] += element_start[e];
    order.resize(atom_count);
    for (std::uint32_t a = 0; a < atom_count; ++a) order[element_start[input.atoms[a].element]++] = a;
  }
  const auto atom_at = [&](std::size_t i) { return by_element ? static_cast<std::uint32_t>(i) : order[i]; };

  // A copy is numbered when its first atom in that order comes: its smallest atom, the root of
  // its class (MinRootUnionFind), so the copies are the roots counted in order. Its node is the
  // smallest among its atoms, all later in the same element's run.
  UnglueResult<D> out;
  std::unique_ptr<std::uint32_t[]> root_copy = uninitialized_array<std::uint32_t>(atom_count);  // set at roots
  parallel_ordered_append(
      threads, atom_count,
      [&](std::size_t i) {
        const std::uint32_t a = atom_at(i);
        return static_cast<std::size_t>(atom_root[a] == a);
      },
      [&](std::size_t total) {
        resize_advised(out.copy_element, total);
        resize_advised(out.copy_node, total);
      },
      [&](std::size_t i, std::size_t copy) {
        const std::uint32_t root = atom_at(i);
        const std::uint32_t element = input.atoms[root].element;
        NodeId node = input.atoms[root].node;
        for (std::size_t j = i + 1; j < atom_count; ++j) {
          const std::uint32_t a = atom_at(j);
          if (input.atoms[a].element != element) break;
          if (atom_root[a] == root) node = std::min(node, input.atoms[a].node);
        }
        root_copy[root] = static_cast<std::uint32_t>(copy);
        out.copy_element[copy] = element;
        out.copy_node[copy] = node;
      },
      kBlock);
  resize_advised(out.atom_copy, atom_count);
  parallel_blocks(threads, atom_count, kBlock, [&](std::size_t begin, std::size_t end) {
    for (std::size_t a = begin; a < end; ++a) out.atom_copy[a] = root_copy[atom_root[a]];
  });
  // The atom-level scratch is done with: released before the vertex copies allocate (the peak
  // memory of meshing lies in this function, BENCHMARKS.md issue 17).
  atom_root.reset();
  root_copy.reset();
  const std::size_t copy_count = out.copy_element.size();
  IMM_ASSERT(copy_count * kArity < kNone, "too many element copies");

  // 2. Vertex copies: D+1 fresh ones per element copy, merged across connected faces.
  MinRootUnionFind vertices(copy_count * kArity, threads);
  parallel_blocks(threads, input.adjacencies.size(), kBlock, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const UnglueAdjacency<D>& adjacency = input.adjacencies[i];
      IMM_ASSERT(adjacency.first < atom_count && adjacency.second < atom_count, "adjacency atom out of range");
      const std::uint32_t element_a = input.atoms[adjacency.first].element;
      const std::uint32_t element_b = input.atoms[adjacency.second].element;
      IMM_ASSERT(element_a != element_b, "adjacency inside one element");
      const std::uint32_t copy_a = out.atom_copy[adjacency.first];
      const std::uint32_t copy_b = out.atom_copy[adjacency.second];
      // The shared face: the vertices of element a that element b has too (exactly D of them).
      std::array<std::pair<int, int>, kArity> shared{};
      int n = 0;
      for (int ia = 0; ia < kArity; ++ia) {
        const int ib = local_index(input.elements[element_b], input.elements[element_a][static_cast<std::size_t>(ia)]);
        if (ib >= 0) shared[static_cast<std::size_t>(n++)] = {ia, ib};
      }
      IMM_ASSERT(n == D, "adjacency between elements " + std::to_string(element_a) + " and " +
                             std::to_string(element_b) + " sharing " + std::to_string(n) + " vertices, not a face");
      for (int k = 0; k < D; ++k)
        vertices.unite(copy_a * kArity + static_cast<std::uint32_t>(shared[static_cast<std::size_t>(k)].first),
                       copy_b * kArity + static_cast<std::uint32_t>(shared[static_cast<std::size_t>(k)].second));
    }
  });

  // 3. Compact numbering, in order of first use by the copies: a class's first use is its
  // smallest vertex copy, its root.
  const std::size_t slot_count = copy_count * kArity;
  const std::unique_ptr<std::uint32_t[]> slot_root = uninitialized_array<std::uint32_t>(slot_count);
  parallel_blocks(threads, slot_count, kBlock, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s) slot_root[s] = vertices.find(static_cast<std::uint32_t>(s));
  });
  vertices.release();
  const std::unique_ptr<std::int32_t[]> class_id = uninitialized_array<std::int32_t>(slot_count);  // set at roots
  parallel_ordered_append(
      threads, slot_count, [&](std::size_t s) { return static_cast<std::size_t>(slot_root[s] == s); },
      [&](std::size_t total) {
        IMM_ASSERT(total < static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()), "too many vertices");
        resize_advised(out.vertex_source, total);
      },
      [&](std::size_t s, std::size_t id) {
        class_id[s] = static_cast<std::int32_t>(id);
        out.vertex_source[id] = input.elements[out.copy_element[s / kArity]][s % kArity];
      },
      kBlock);
  resize_advised(out.copies, copy_count);
  parallel_blocks(threads, copy_count, kBlock, [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const auto& element = input.elements[out.copy_element[c]];
      for (int k = 0; k < kArity; ++k) {
        const std::int32_t id = class_id[slot_root[c * kArity + static_cast<std::size_t>(k)]];
        IMM_ASSERT(out.vertex_source[static_cast<std::size_t>(id)] == element[k],
                   "merged vertex copies of two different background vertices");
        out.copies[c][k] = id;
      }
    }
  });
  return out;
}

template UnglueResult<2> unglue<2>(const UnglueInput<2>&, unsigned);
template UnglueResult<3> unglue<3>(const UnglueInput<3>&, unsigned);

template <int D>
AtomExpansion<D>::AtomExpansion(const CellComplex<D>& complex, const Immersion& immersion,
                                const std::vector<std::uint32_t>& first, const std::vector<RegionId>& region,
                                std::vector<std::array<std::int32_t, D + 1>> elements, unsigned threads)
    : complex_(complex), immersion_(immersion), region_(region), edges_across_(complex.patch_count()) {
  input_.elements = std::move(elements);
  IMM_ASSERT(first.size() == input_.elements.size() + 1 && first.back() == region.size(),
             "local regions do not match the elements");
  atom_first_.reserve(region.size());
  advise_huge_pages(atom_first_);
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
        resize_advised(atoms, total);
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
void AtomExpansion<D>::connect(std::uint32_t first, std::uint32_t second) {
  const CellId cell = complex_.cell_of(region_[first]);
  if (!cell.is_valid()) return;
  for (int k = 0; k < complex_.winding_number(cell); ++k)
    input_.adjacencies.push_back({atom_first_[first] + static_cast<std::uint32_t>(k),
                                  atom_first_[second] + static_cast<std::uint32_t>(k)});
}

template <int D>
void AtomExpansion<D>::connect_across(std::uint32_t inner, std::uint32_t outer, PatchId patch) {
  for (const ImmersionEdge& e : edges_across_[patch]) input_.adjacencies.push_back({atom(inner, e.inner), atom(outer, e.outer)});
}

template class AtomExpansion<2>;
template class AtomExpansion<3>;

}  // namespace imm
