#include "support/brute_force.h"

#include <algorithm>
#include <map>
#include <numeric>

#include "support/immersion_checker.h"

namespace imm::test_support {
namespace {

/// One way to complete a patch: its owner and its edges.
struct PatchChoice {
  NodeId owner;
  std::vector<ImmersionEdge> edges;
};

std::vector<std::vector<int>> all_permutations(int n) {
  std::vector<int> p(static_cast<std::size_t>(n));
  std::iota(p.begin(), p.end(), 0);
  std::vector<std::vector<int>> out;
  do {
    out.push_back(p);
  } while (std::next_permutation(p.begin(), p.end()));
  return out;
}

}  // namespace

template <int D>
double brute_force_candidate_count(const CellComplex<D>& complex) {
  double count = 1;
  for (std::size_t i = 0; i < complex.patch_count(); ++i) {
    const int w = complex.winding_number(complex.sides(PatchId(i)).negative);
    for (int k = 2; k <= w; ++k) count *= k;
  }
  return count;
}

template <int D>
std::size_t for_each_candidate(const CellComplex<D>& complex,
                               const std::function<void(const Immersion&)>& visit,
                               std::size_t max_candidates) {
  IMM_ASSERT(brute_force_candidate_count(complex) <= static_cast<double>(max_candidates),
             "brute force: too many candidate graphs");
  const NodeLayout layout(complex);
  const auto copies = [&](CellId c) {
    std::vector<NodeId> out;
    if (!c.is_valid()) return out;
    for (int k = 0; k < complex.winding_number(c); ++k) out.push_back(layout.node(c, k));
    return out;
  };

  // Every completion of every patch.
  std::vector<std::vector<PatchChoice>> choices(complex.patch_count());
  for (std::size_t i = 0; i < complex.patch_count(); ++i) {
    const PatchId p(i);
    const std::vector<NodeId> inner = copies(complex.cell_of(complex.sides(p).negative));
    const std::vector<NodeId> outer = copies(complex.cell_of(complex.sides(p).positive));
    IMM_ASSERT(inner.size() == outer.size() + 1, "brute force: winding numbers across a patch");
    for (std::size_t o = 0; o < inner.size(); ++o) {
      std::vector<NodeId> rest;
      for (std::size_t k = 0; k < inner.size(); ++k) {
        if (k != o) rest.push_back(inner[k]);
      }
      for (const std::vector<int>& perm : all_permutations(static_cast<int>(outer.size()))) {
        PatchChoice choice{inner[o], {}};
        for (std::size_t k = 0; k < rest.size(); ++k) {
          choice.edges.push_back({rest[k], outer[static_cast<std::size_t>(perm[k])], p});
        }
        choices[i].push_back(std::move(choice));
      }
    }
  }

  std::size_t count = 0;
  std::vector<std::size_t> pick(complex.patch_count(), 0);
  while (true) {
    ++count;
    Immersion im;
    im.layout = layout;
    im.owner = IdMap<PatchId, NodeId>(complex.patch_count());
    for (std::size_t i = 0; i < complex.patch_count(); ++i) {
      const PatchChoice& choice = choices[i][pick[i]];
      im.owner[PatchId(i)] = choice.owner;
      im.edges.insert(im.edges.end(), choice.edges.begin(), choice.edges.end());
    }
    std::sort(im.edges.begin(), im.edges.end());
    visit(im);
    std::size_t i = 0;
    while (i < pick.size() && ++pick[i] == choices[i].size()) pick[i++] = 0;
    if (i == pick.size()) break;
  }
  return count;
}

template <int D>
BruteForceResult brute_force_immersions(const CellComplex<D>& complex, std::size_t max_candidates) {
  const NodeLayout layout(complex);
  // Relabellings: every permutation of the copies of every cell.
  std::vector<std::vector<std::vector<int>>> cell_perms(complex.cell_count());
  double relabellings = 1;
  for (std::size_t c = 0; c < complex.cell_count(); ++c) {
    cell_perms[c] = all_permutations(complex.winding_number(CellId(c)));
    relabellings *= static_cast<double>(cell_perms[c].size());
  }
  IMM_ASSERT(relabellings <= 100000, "brute force: too many relabellings");
  const auto iso_key = [&](const Immersion& im) {
    std::vector<int> best;
    std::vector<std::size_t> pick(complex.cell_count(), 0);
    std::vector<NodeId> map(layout.node_count());
    while (true) {
      for (std::size_t n = 0; n < layout.node_count(); ++n) {
        const CellId c = layout.cell(NodeId(n));
        map[n] = layout.node(c, cell_perms[c.index()][pick[c.index()]][static_cast<std::size_t>(
                                    layout.copy(NodeId(n)))]);
      }
      std::vector<int> key;
      for (NodeId o : im.owner) key.push_back(map[o.index()].value());
      std::vector<ImmersionEdge> edges;
      for (const ImmersionEdge& e : im.edges) edges.push_back({map[e.inner.index()], map[e.outer.index()], e.patch});
      std::sort(edges.begin(), edges.end());
      for (const ImmersionEdge& e : edges) {
        key.insert(key.end(), {e.inner.value(), e.outer.value(), e.patch.value()});
      }
      if (best.empty() || key < best) best = std::move(key);
      std::size_t c = 0;
      while (c < pick.size() && ++pick[c] == cell_perms[c].size()) pick[c++] = 0;
      if (c == pick.size()) break;
    }
    return best;
  };

  BruteForceResult result;
  std::map<std::vector<int>, std::size_t> classes;
  result.candidates = for_each_candidate(
      complex,
      [&](const Immersion& im) {
        if (!check_immersion(complex, im).empty()) return;
        ++result.valid;
        if (classes.emplace(iso_key(im), result.classes.size()).second) result.classes.push_back(im);
      },
      max_candidates);
  return result;
}

template std::size_t for_each_candidate<2>(const CellComplex<2>&,
                                           const std::function<void(const Immersion&)>&, std::size_t);
template std::size_t for_each_candidate<3>(const CellComplex<3>&,
                                           const std::function<void(const Immersion&)>&, std::size_t);
template double brute_force_candidate_count<2>(const CellComplex<2>&);
template double brute_force_candidate_count<3>(const CellComplex<3>&);
template BruteForceResult brute_force_immersions<2>(const CellComplex<2>&, std::size_t);
template BruteForceResult brute_force_immersions<3>(const CellComplex<3>&, std::size_t);

}  // namespace imm::test_support
