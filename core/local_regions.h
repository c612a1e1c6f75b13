// The local regions of a background mesh (paper §7.1), for triangles (D = 2) and tetrahedra
// (D = 3) alike: what the element cutting (dim2/virtual_triangles*.cpp, dim3/virtual_tets*.cpp)
// finds and the meshers (dim2/mesh2.cpp, dim3/mesh3.cpp) turn into atoms of the
// duplicate-and-connect driver (core/unglue.h).
//
// A local region is a connected component of (background element minus the input); each lies in
// exactly one region of the complex. An element the input does not meet has exactly one. Local
// regions are numbered element by element: those of element e are first[e] .. first[e+1]-1.
//  - a fusion joins two local regions of one element on the two sides of a piece of a patch
//    inside it (the two are one element copy wherever the immersion glues across the patch);
//  - an adjacency joins local regions of two elements sharing a face (D vertices; not stored,
//    it follows from the two elements) whose parts of the face meet along a positive measure;
//    with an invalid patch the contact is free of the input (both lie in one region), otherwise
//    it lies on the patch, `first` on its inner side.
// Regions of local regions that no input piece bounds follow from the input-free adjacencies
// (union-find) and, for a component with no known member, one exact point location.
//
// Nothing here depends on D beyond the arity of faces (D) and of barycentric weights (D + 1).
// What one dimension records beyond this (2D: curve pieces per local region; 3D: cut-triangle
// pieces and clipping statistics) lives in a struct of that dimension deriving from this one.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <tuple>
#include <vector>

#include "core/diagnostics.h"
#include "core/huge_pages.h"
#include "core/ids.h"
#include "core/parallel.h"
#include "core/unglue.h"
#include "core/union_find.h"

namespace imm {

template <int D>
struct LocalRegions {
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  /// Local regions of element e are first[e] .. first[e+1]-1 (size: elements + 1 when complete).
  std::vector<std::uint32_t> first;
  std::vector<RegionId> region;         ///< per local region
  std::vector<std::uint32_t> element;   ///< per local region: its background element

  /// Two local regions of one element on the two sides of a piece of `patch`.
  struct Fusion {
    std::uint32_t inner;  ///< on the patch's negative (inner) side
    std::uint32_t outer;  ///< on its positive side
    PatchId patch;
  };
  std::vector<Fusion> fusions;  ///< one per (element, patch, pair of local regions)

  /// Two local regions of two elements sharing a face (face()). Invalid `patch`: the contact is
  /// free of the input and both lie in one region. Valid: the input runs in the face along
  /// `patch`, `first` on its inner side, `second` on its outer side (2D only: in 3D the input
  /// meets a background face generically, never along a positive area). The face is not stored:
  /// it is the D vertices the two elements share (12 of 24 bytes in 3D, on the largest array of
  /// meshing at scale; BENCHMARKS.md, issue 17).
  struct Adjacency {
    std::uint32_t first;
    std::uint32_t second;
    PatchId patch;
  };
  std::vector<Adjacency> adjacencies;

  /// The face two elements share: the D vertex ids both have, ascending.
  /// @throws InvariantError unless they share exactly D (the face pairing refuses two elements
  /// with the same vertices).
  template <class Element>
  static std::array<int, D> shared_face(const Element& a, const Element& b) {
    std::array<int, D> face{};
    int n = 0;
    for (const auto v : a)
      if (std::find(b.begin(), b.end(), v) != b.end()) {
        IMM_ASSERT(n < D, "an adjacency between two elements with the same vertices");
        face[static_cast<std::size_t>(n++)] = static_cast<int>(v);
      }
    IMM_ASSERT(n == D, "an adjacency between two elements that share no face");
    std::sort(face.begin(), face.end());
    return face;
  }
  /// The face across which adjacency `a` joins its local regions, from the background
  /// `elements` (D + 1 vertex ids each) these local regions were computed on.
  template <class Elements>
  [[nodiscard]] std::array<int, D> face(const Adjacency& a, const Elements& elements) const {
    return shared_face(elements[element[a.first]], elements[element[a.second]]);
  }

  /// Where each input vertex (input order) sits: a local region on the inner side of its patch
  /// touching the vertex, and exact barycentric coordinates in that element, rounded once.
  struct VertexLocation {
    std::uint32_t local_region = kNone;  ///< kNone: not covered by the background
    PatchId patch;
    std::array<double, D + 1> weights{};
  };
  std::vector<VertexLocation> vertices;

  std::size_t cut_elements = 0;     ///< elements with two or more local regions
  std::size_t point_locations = 0;  ///< exact point locations needed for flood components

  // ---- building, element by element in element order ---------------------------------------

  /// Opens the next element: its local regions are the ones added until end_element().
  void begin_element() { first.push_back(static_cast<std::uint32_t>(region.size())); }
  /// A new local region of element e (the open one). @return its id.
  std::uint32_t add_local_region(std::uint32_t e, RegionId r = RegionId()) {
    region.push_back(r);
    element.push_back(e);
    return static_cast<std::uint32_t>(region.size() - 1);
  }
  /// Closes the open element (counts it as cut when it has two local regions or more).
  void end_element() {
    if (region.size() - first.back() > 1) ++cut_elements;
  }
  /// Appends element e with `regions` (numbered 0 .. size-1 within e) and `local_fusions` between
  /// them. @return the id of its first local region.
  std::uint32_t append_element(std::uint32_t e, const std::vector<RegionId>& regions,
                               const std::vector<Fusion>& local_fusions) {
    begin_element();
    const std::uint32_t base = first.back();
    for (RegionId r : regions) add_local_region(e, r);
    end_element();
    for (const Fusion& f : local_fusions) fusions.push_back({base + f.inner, base + f.outer, f.patch});
    return base;
  }
  /// After the last element: first[] gets its closing entry.
  void finish() { first.push_back(static_cast<std::uint32_t>(region.size())); }

  /// Local region lr of `regions` lies in region r (already known to lie in r, or unknown).
  /// @throws InvariantError when it is known to lie in another region.
  static void set_region(std::vector<RegionId>& regions, std::uint32_t lr, RegionId r) {
    IMM_ASSERT(!regions[lr].is_valid() || regions[lr] == r, "a local region lies in two regions");
    regions[lr] = r;
  }

  /// Sorts and de-duplicates the fusions of one element (each pair is found once per piece).
  static void normalise(std::vector<Fusion>& list) {
    std::sort(list.begin(), list.end(), [](const Fusion& a, const Fusion& b) {
      return std::tie(a.inner, a.outer, a.patch) < std::tie(b.inner, b.outer, b.patch);
    });
    list.erase(std::unique(list.begin(), list.end(),
                           [](const Fusion& a, const Fusion& b) {
                             return a.inner == b.inner && a.outer == b.outer && a.patch == b.patch;
                           }),
               list.end());
  }
  /// Sorts and de-duplicates adjacencies (each contact is found once per part of a face; two
  /// elements share one face, so the pair of local regions and the patch say which).
  static void normalise(std::vector<Adjacency>& list) {
    std::sort(list.begin(), list.end(), [](const Adjacency& a, const Adjacency& b) {
      return std::tie(a.first, a.second, a.patch) < std::tie(b.first, b.second, b.patch);
    });
    list.erase(std::unique(list.begin(), list.end(),
                           [](const Adjacency& a, const Adjacency& b) {
                             return a.first == b.first && a.second == b.second && a.patch == b.patch;
                           }),
               list.end());
  }
  /// Appends one element's fusions, sorted and without repeats.
  void add_fusions(std::vector<Fusion> list) {
    normalise(list);
    fusions.insert(fusions.end(), list.begin(), list.end());
  }

  // ---- regions ---------------------------------------------------------------------------

  /// Gives every local region its region of the complex: local regions joined by an input-free
  /// adjacency lie in one region; each such component takes the region of any member known from
  /// an input piece, and a component with none is located once, by `locate(lr)` on its smallest
  /// member (exact point location, on the calling thread, in member order; counted in
  /// point_locations). The unions and the passes over local regions run on `threads` threads;
  /// every component is rooted at its smallest member (MinRootUnionFind), so the regions and the
  /// located members are the same for every count.
  /// @throws InvariantError when two different known regions meet across an input-free adjacency.
  template <class Locate>
  void resolve_regions(const Locate& locate, unsigned threads = 1) {
    constexpr std::size_t kBlock = 1 << 14;
    const std::size_t n = region.size();
    MinRootUnionFind same(n, threads);
    parallel_blocks(threads, adjacencies.size(), kBlock, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        if (!adjacencies[i].patch.is_valid()) same.unite(adjacencies[i].first, adjacencies[i].second);
    });
    // Per root, the region a member is known to lie in (a compare-and-swap from "unknown": any
    // two known members of a component must agree, whichever writes first).
    using Raw = typename RegionId::value_type;
    const std::unique_ptr<Raw[]> root_region = uninitialized_array<Raw>(n);
    parallel_blocks(threads, n, kBlock, [&](std::size_t begin, std::size_t end) {
      for (std::size_t lr = begin; lr < end; ++lr) root_region[lr] = RegionId::kInvalid;
    });
    parallel_blocks(threads, n, kBlock, [&](std::size_t begin, std::size_t end) {
      for (std::size_t lr = begin; lr < end; ++lr) {
        if (!region[lr].is_valid()) continue;
        std::atomic_ref<Raw> r(root_region[same.find(static_cast<std::uint32_t>(lr))]);
        Raw expected = RegionId::kInvalid;
        if (!r.compare_exchange_strong(expected, region[lr].value(), std::memory_order_relaxed))
          IMM_ASSERT(expected == region[lr].value(), "two regions meet across an element face free of the input");
      }
    });
    // Components with no known member: their roots (smallest members), in order, located here.
    std::vector<std::vector<std::uint32_t>> unknown((n + kBlock - 1) / kBlock);
    parallel_blocks(threads, n, kBlock, [&](std::size_t begin, std::size_t end) {
      for (std::size_t lr = begin; lr < end; ++lr)
        if (!RegionId(root_region[lr]).is_valid() && same.find(static_cast<std::uint32_t>(lr)) == lr)
          unknown[begin / kBlock].push_back(static_cast<std::uint32_t>(lr));
    });
    for (const std::vector<std::uint32_t>& roots : unknown)
      for (const std::uint32_t root : roots) {
        root_region[root] = locate(root).value();
        ++point_locations;
      }
    parallel_blocks(threads, n, kBlock, [&](std::size_t begin, std::size_t end) {
      for (std::size_t lr = begin; lr < end; ++lr)
        if (!region[lr].is_valid()) region[lr] = RegionId(root_region[same.find(static_cast<std::uint32_t>(lr))]);
    });
  }

  // ---- atoms -----------------------------------------------------------------------------

  /// Glues the atoms of one immersion (core/unglue.h) along these fusions and adjacencies: across
  /// a fusion or an adjacency on a patch through the graph's edges across the patch, across an
  /// input-free adjacency copy by copy; on `threads` threads (the same lists for every count).
  void glue(AtomExpansion<D>& atoms, unsigned threads = 1) const { atoms.glue(fusions, adjacencies, threads); }
};

}  // namespace imm
