#include "support/hand_complexes.h"

#include <algorithm>
#include <numeric>
#include <random>

namespace imm::test_support {
namespace {

/// Portable seeded choices (the standard distributions differ between library vendors).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed * 0x9E3779B97F4A7C15ULL + 1) {}
  int below(int n) { return static_cast<int>(engine_() % static_cast<std::uint64_t>(n)); }
  template <class T>
  void shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[static_cast<std::size_t>(below(static_cast<int>(i)))]);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace

template <int D>
CellComplex<D> build(const ComplexSpec& spec) {
  CellComplex<D> complex;
  for (std::size_t r = 0; r < spec.regions.size(); ++r) {
    complex.add_region(spec.regions[r].winding, Rational(r == 0 ? 0 : 1),
                       spec.regions[r].simply_connected);
  }
  for (const ComplexSpec::Patch& p : spec.patches) {
    complex.add_patch(PatchSides{RegionId(p.positive), RegionId(p.negative)});
  }
  for (const ComplexSpec::Arc& a : spec.arcs) {
    ArcJunctions j;
    for (int k = 0; k < 4; ++k) {
      j.patch[k] = PatchId(a.patch[k]);
      j.wedge[k] = RegionId(a.wedge[k]);
    }
    complex.add_arc(j);
  }
  complex.finalize();
  return complex;
}

template CellComplex<2> build<2>(const ComplexSpec&);
template CellComplex<3> build<3>(const ComplexSpec&);

ComplexSpec shuffled(const ComplexSpec& spec, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<int> region_order(spec.regions.size());
  std::iota(region_order.begin(), region_order.end(), 0);
  std::vector<int> tail(region_order.begin() + 1, region_order.end());
  rng.shuffle(tail);
  std::copy(tail.begin(), tail.end(), region_order.begin() + 1);  // new position -> old region
  std::vector<int> region_new(spec.regions.size());
  for (std::size_t i = 0; i < region_order.size(); ++i) region_new[region_order[i]] = static_cast<int>(i);

  std::vector<int> patch_order(spec.patches.size());
  std::iota(patch_order.begin(), patch_order.end(), 0);
  rng.shuffle(patch_order);
  std::vector<int> patch_new(spec.patches.size());
  for (std::size_t i = 0; i < patch_order.size(); ++i) patch_new[patch_order[i]] = static_cast<int>(i);

  std::vector<int> arc_order(spec.arcs.size());
  std::iota(arc_order.begin(), arc_order.end(), 0);
  rng.shuffle(arc_order);

  ComplexSpec out;
  out.name = spec.name + " (shuffled " + std::to_string(seed) + ")";
  for (int old : region_order) out.regions.push_back(spec.regions[old]);
  for (int old : patch_order) {
    out.patches.push_back({region_new[spec.patches[old].negative], region_new[spec.patches[old].positive]});
  }
  for (int old : arc_order) {
    const ComplexSpec::Arc& a = spec.arcs[old];
    const int turn = rng.below(4);
    const bool reverse = rng.below(2) == 1;
    // Reversal maps junction k to -k and wedge k to -k-1; then the cycle is rotated by `turn`.
    ComplexSpec::Arc r = a;
    if (reverse) {
      for (int k = 0; k < 4; ++k) {
        r.patch[k] = a.patch[(4 - k) % 4];
        r.wedge[k] = a.wedge[(7 - k) % 4];
      }
    }
    ComplexSpec::Arc b;
    for (int k = 0; k < 4; ++k) {
      b.patch[k] = patch_new[r.patch[(k + turn) % 4]];
      b.wedge[k] = region_new[r.wedge[(k + turn) % 4]];
    }
    out.arcs.push_back(b);
  }
  return out;
}

ComplexSpec disjoint_union(const ComplexSpec& a, const ComplexSpec& b) {
  ComplexSpec out = a;
  out.name = a.name + " + " + b.name;
  const int offset = static_cast<int>(a.regions.size()) - 1;
  const auto region = [&](int r) { return r == 0 ? 0 : r + offset; };
  for (std::size_t r = 1; r < b.regions.size(); ++r) out.regions.push_back(b.regions[r]);
  const int patch_offset = static_cast<int>(a.patches.size());
  for (const auto& p : b.patches) out.patches.push_back({region(p.negative), region(p.positive)});
  for (const auto& arc : b.arcs) {
    ComplexSpec::Arc c;
    for (int k = 0; k < 4; ++k) {
      c.patch[k] = arc.patch[k] + patch_offset;
      c.wedge[k] = region(arc.wedge[k]);
    }
    out.arcs.push_back(c);
  }
  return out;
}

ComplexSpec enclosed(const ComplexSpec& spec) {
  ComplexSpec out;
  out.name = spec.name + " in a circle";
  out.regions.push_back({0, true});
  for (std::size_t r = 0; r < spec.regions.size(); ++r) {
    out.regions.push_back({spec.regions[r].winding + 1, r == 0 ? false : spec.regions[r].simply_connected});
  }
  for (const auto& p : spec.patches) out.patches.push_back({p.negative + 1, p.positive + 1});
  out.patches.push_back({1, 0});
  for (const auto& arc : spec.arcs) {
    ComplexSpec::Arc c = arc;
    for (int& w : c.wedge) ++w;
    out.arcs.push_back(c);
  }
  return out;
}

ComplexSpec circle() {
  ComplexSpec s;
  s.name = "circle";
  s.regions = {{0, true}, {1, true}};
  s.patches = {{1, 0}};
  return s;
}

ComplexSpec nested_circles() {
  ComplexSpec s;
  s.name = "nested circles";
  // 0 outside, 1 ring (w 1), 2 inner disk (w 2).
  s.regions = {{0, true}, {1, false}, {2, true}};
  s.patches = {{1, 0}, {2, 1}};
  return s;
}

ComplexSpec nested_annulus_choice() {
  ComplexSpec s;
  s.name = "nested annulus choice";
  // 0 outside, 1 ring A (w 1), 2 ring B (w 2), 3 disk C (w 1) inside the clockwise circle.
  s.regions = {{0, true}, {1, false}, {2, false}, {1, true}};
  s.patches = {{1, 0}, {2, 1}, {2, 3}};
  return s;
}

ComplexSpec limacon() {
  ComplexSpec s;
  s.name = "limacon";
  // 0 outside, 1 region between the loops (w 1, touches itself at the crossing), 2 inner loop.
  // P0 = big loop, P1 = small loop; each sheet through the crossing joins P0 to P1.
  s.regions = {{0, true}, {1, true}, {2, true}};
  s.patches = {{1, 0}, {2, 1}};
  s.arcs = {{{0, 0, 1, 1}, {0, 1, 2, 1}}};
  return s;
}

ComplexSpec double_limacon_ring() {
  ComplexSpec s;
  s.name = "double limacon ring";
  // 0 outside, 1 outer crescent (w 1), 2 ring R (w 2, not simply connected), 3 inner crescent
  // (w 1), 4 centre (w 0). Outer curve: limaçon P0 (big), P1 (small). Inner curve: a clockwise
  // limaçon with P2 (its outer strand, R on the inner side) and P3 (its inner strand).
  s.regions = {{0, true}, {1, true}, {2, false}, {1, true}, {0, true}};
  s.patches = {{1, 0}, {2, 1}, {2, 3}, {3, 4}};
  s.arcs = {{{0, 0, 1, 1}, {0, 1, 2, 1}}, {{2, 2, 3, 3}, {2, 3, 4, 3}}};
  return s;
}

ComplexSpec band() {
  ComplexSpec s;
  s.name = "band";
  // A strip bent into a spiral, its two ends overlapping. Regions: 0 outside, 1 the hole the
  // spiral goes around (w 0), 2 the strip minus the overlap (w 1, cut open at the two crossings),
  // 3 the overlap (w 2). Patches: Pa = outer edge (body|outside), Pb = far end cap + edge inside
  // the overlap (overlap|body), Pc = inner edge (body|hole), Pd = near end cap + edge (overlap|
  // body). Crossing X: A's lower edge meets B's end cap; crossing Y: B's upper edge meets A's cap.
  s.regions = {{0, true}, {0, true}, {1, true}, {2, true}};
  s.patches = {{2, 0}, {3, 2}, {2, 1}, {3, 2}};
  s.arcs = {{{3, 1, 2, 2}, {3, 2, 1, 2}},   // X: Pd, Pb, Pc, Pc around overlap, body, hole, body
            {{0, 0, 1, 3}, {0, 2, 3, 2}}};  // Y: Pa, Pa, Pb, Pd around outside, body, overlap, body
  return s;
}

ComplexSpec fig9() {
  ComplexSpec s;
  s.name = "fig9";
  // Regions 1..4 are cells 0..3 of the caption. Patch sides from the caption's agreement marks:
  // P0, P1 (cell 0 | outside), P2, P3 (cell 1 | cell 0), P4 (cell 1 | cell 2), P5 (cell 2 |
  // outside), P6 (cell 1 | cell 3), P7 (cell 3 | outside). Arcs: the topological-neighbour pairs
  // of the caption are opposite junctions; the wedge between two consecutive junctions is the
  // region their patches share, which fixes each cycle up to reflection.
  s.regions = {{0, true}, {1, true}, {2, true}, {1, true}, {1, true}};
  s.patches = {{1, 0}, {1, 0}, {2, 1}, {2, 1}, {2, 3}, {3, 0}, {2, 4}, {4, 0}};
  s.arcs = {
      {{1, 1, 2, 3}, {0, 1, 2, 1}},  // Arc 0: (P1, P2), (P1, P3); cell 0 self-touches
      {{0, 2, 4, 5}, {1, 2, 3, 0}},  // Arc 1: (P0, P4), (P2, P5)
      {{0, 3, 6, 7}, {1, 2, 4, 0}},  // Arc 2: (P0, P6), (P3, P7)
      {{4, 5, 7, 6}, {3, 0, 4, 2}},  // Arc 3: (P4, P7), (P5, P6)
  };
  return s;
}

namespace {

/// Regions of winding numbers 0..max_winding (one or two per level) and `arcs` arcs with the
/// winding pattern (w, w + 1, w + 2, w + 1) up to rotation, w drawn from min_base..max_winding - 2;
/// half of the arcs self-touching, patches reused between the same two regions two times in three.
ComplexSpec random_arcs(std::uint64_t seed, const std::string& name, int max_winding, int min_base,
                        int arcs) {
  Rng rng(seed);
  ComplexSpec s;
  s.name = name + " " + std::to_string(seed);
  std::vector<std::vector<int>> level(static_cast<std::size_t>(max_winding) + 1);
  s.regions.push_back({0, true});
  level[0].push_back(0);
  for (int w = 0; w <= max_winding; ++w) {
    const int count = (w == 0 ? rng.below(2) : 1 + rng.below(2));
    for (int i = 0; i < count; ++i) {
      level[w].push_back(static_cast<int>(s.regions.size()));
      s.regions.push_back({w, true});
    }
  }
  const auto pick = [&](int w) { return level[w][rng.below(static_cast<int>(level[w].size()))]; };
  const auto patch_between = [&](int negative, int positive, bool reuse) {
    std::vector<int> existing;
    for (std::size_t i = 0; i < s.patches.size(); ++i) {
      if (s.patches[i].negative == negative && s.patches[i].positive == positive) existing.push_back(static_cast<int>(i));
    }
    if (reuse && !existing.empty()) return existing[rng.below(static_cast<int>(existing.size()))];
    s.patches.push_back({negative, positive});
    return static_cast<int>(s.patches.size()) - 1;
  };
  for (int i = 0; i < arcs; ++i) {
    const int base = min_base + rng.below(max_winding - 1 - min_base);
    const int turn = rng.below(4);
    constexpr std::array<int, 4> kPattern{0, 1, 2, 1};
    ComplexSpec::Arc arc;
    for (int k = 0; k < 4; ++k) arc.wedge[k] = pick(base + kPattern[(k + turn) % 4]);
    if (rng.below(2) == 0) arc.wedge[(5 - turn) % 4] = arc.wedge[(3 - turn) % 4];  // self-touching
    for (int k = 0; k < 4; ++k) {
      const int a = arc.wedge[(k + 3) % 4], b = arc.wedge[k];
      const bool a_inner = s.regions[a].winding > s.regions[b].winding;
      arc.patch[k] = patch_between(a_inner ? a : b, a_inner ? b : a, rng.below(3) != 0);
    }
    s.arcs.push_back(arc);
  }
  // Every cell gets at least one B-patch.
  for (std::size_t r = 1; r < s.regions.size(); ++r) {
    const int w = s.regions[r].winding;
    if (w == 0) continue;
    bool has = false;
    for (const auto& p : s.patches) has = has || p.negative == static_cast<int>(r) || p.positive == static_cast<int>(r);
    if (!has) patch_between(static_cast<int>(r), pick(w - 1), false);
  }
  return s;
}

}  // namespace

ComplexSpec random_complex(std::uint64_t seed, int max_winding, int arcs) {
  return random_arcs(seed, "random", max_winding, /*min_base=*/0, arcs);
}

ComplexSpec random_enclosed_complex(std::uint64_t seed, int arcs) {
  return random_arcs(seed, "random enclosed", /*max_winding=*/4, /*min_base=*/1, arcs);
}

}  // namespace imm::test_support
