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
//  - an adjacency joins local regions of two elements sharing a face (D vertices) whose parts of
//    the face meet along a positive measure; with an invalid patch the contact is free of the
//    input (both lie in one region), otherwise it lies on the patch, `first` on its inner side.
// Regions of local regions that no input piece bounds follow from the input-free adjacencies
// (union-find) and, for a component with no known member, one exact point location.
//
// Nothing here depends on D beyond the arity of faces (D) and of barycentric weights (D + 1).
// What one dimension records beyond this (2D: curve pieces per local region; 3D: cut-triangle
// pieces and clipping statistics) lives in a struct of that dimension deriving from this one.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <tuple>
#include <vector>

#include "core/diagnostics.h"
#include "core/ids.h"
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

  /// Two local regions of two elements sharing `face`. Invalid `patch`: the contact is free of the
  /// input and both lie in one region. Valid: the input runs in the face along `patch`, `first`
  /// on its inner side, `second` on its outer side (2D only: in 3D the input meets a background
  /// face generically, never along a positive area).
  struct Adjacency {
    std::uint32_t first;
    std::uint32_t second;
    PatchId patch;
    std::array<int, D> face;  ///< background vertex ids
  };
  std::vector<Adjacency> adjacencies;

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
  /// Sorts and de-duplicates adjacencies (each contact is found once per part of a face).
  static void normalise(std::vector<Adjacency>& list) {
    std::sort(list.begin(), list.end(), [](const Adjacency& a, const Adjacency& b) {
      return std::tie(a.first, a.second, a.patch, a.face) < std::tie(b.first, b.second, b.patch, b.face);
    });
    list.erase(std::unique(list.begin(), list.end(),
                           [](const Adjacency& a, const Adjacency& b) {
                             return a.first == b.first && a.second == b.second && a.patch == b.patch &&
                                    a.face == b.face;
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
  /// an input piece, and a component with none is located once, by `locate(lr)` on one member
  /// (exact point location; counted in point_locations).
  /// @throws InvariantError when two different known regions meet across an input-free adjacency.
  template <class Locate>
  void resolve_regions(const Locate& locate) {
    const std::size_t n = region.size();
    UnionFind same(n);
    for (const Adjacency& a : adjacencies)
      if (!a.patch.is_valid()) same.unite(a.first, a.second);
    std::vector<RegionId> root_region(n);
    for (std::uint32_t lr = 0; lr < n; ++lr) {
      if (!region[lr].is_valid()) continue;
      RegionId& r = root_region[same.find(lr)];
      IMM_ASSERT(!r.is_valid() || r == region[lr], "two regions meet across an element face free of the input");
      r = region[lr];
    }
    for (std::uint32_t lr = 0; lr < n; ++lr) {
      if (region[lr].is_valid()) continue;
      RegionId& r = root_region[same.find(lr)];
      if (!r.is_valid()) {
        r = locate(lr);
        ++point_locations;
      }
      region[lr] = r;
    }
  }

  // ---- atoms -----------------------------------------------------------------------------

  /// Glues the atoms of one immersion (core/unglue.h) along these fusions and adjacencies: across
  /// a fusion or an adjacency on a patch through the graph's edges across the patch, across an
  /// input-free adjacency copy by copy; on `threads` threads (the same lists for every count).
  void glue(AtomExpansion<D>& atoms, unsigned threads = 1) const { atoms.glue(fusions, adjacencies, threads); }
};

}  // namespace imm
