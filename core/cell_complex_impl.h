// Template definitions of CellComplex<D>; included only by core/instantiate.cpp.
#pragma once
#include "core/cell_complex.h"

#include <algorithm>
#include <sstream>

namespace imm {

template <int D>
  requires ImmersionDim<DimTraits<D>>
RegionId CellComplex<D>::add_region(int winding_number, Rational measure, bool simply_connected) {
  IMM_ASSERT(!finalized_, "complex already finalized");
  IMM_ASSERT(!winding_.empty() || winding_number == 0, "region 0 must be the unbounded region");
  winding_.push_back(winding_number);
  measure_.push_back(std::move(measure));
  simply_connected_.push_back(simply_connected ? 1 : 0);
  return RegionId(winding_.size() - 1);
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
PatchId CellComplex<D>::add_patch(PatchSides sides) {
  IMM_ASSERT(!finalized_, "complex already finalized");
  IMM_ASSERT(sides.positive.is_valid() && sides.positive.index() < winding_.size() &&
                 sides.negative.is_valid() && sides.negative.index() < winding_.size(),
             "patch side is not a region");
  std::ostringstream msg;
  msg << "winding must drop by one across a patch: negative side " << sides.negative << " has "
      << winding_[sides.negative] << ", positive side " << sides.positive << " has "
      << winding_[sides.positive];
  IMM_ASSERT(winding_[sides.negative] == winding_[sides.positive] + 1, msg.str());
  return sides_.push_back(sides);
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
ArcId CellComplex<D>::add_arc(const ArcJunctions& arc) {
  IMM_ASSERT(!finalized_, "complex already finalized");
  for (int k = 0; k < 4; ++k) {
    const PatchId p = arc.patch[k];
    IMM_ASSERT(p.is_valid() && p.index() < sides_.size(), "junction patch out of range");
    const RegionId before = arc.wedge[(k + 3) % 4];
    const RegionId after = arc.wedge[k];
    const PatchSides& s = sides_[p];
    const bool separates = (s.positive == before && s.negative == after) ||
                           (s.negative == before && s.positive == after);
    IMM_ASSERT(separates, "junction patch does not separate its two wedges");
  }
  return arcs_.push_back(arc);
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
void CellComplex<D>::finalize() {
  IMM_ASSERT(!finalized_, "complex already finalized");
  region_cell_ = IdMap<RegionId, CellId>(winding_.size());
  cell_region_ = {};
  for (RegionId r : ids<RegionId>(winding_.size())) {
    if (winding_[r] != 0) {
      IMM_ASSERT(r != kOutsideRegion, "the unbounded region must have winding number 0");
      region_cell_[r] = cell_region_.push_back(r);
    }
  }
  b_patches_ = IdMap<CellId, std::vector<BPatch>>(cell_region_.size());
  for (PatchId p : ids<PatchId>(sides_.size())) {
    const PatchSides& s = sides_[p];
    IMM_ASSERT(region_cell_[s.negative].is_valid(), "the negative side of a patch must be a cell");
    b_patches_[region_cell_[s.negative]].push_back({p, true});
    if (region_cell_[s.positive].is_valid()) b_patches_[region_cell_[s.positive]].push_back({p, false});
  }
  patch_arcs_ = IdMap<PatchId, std::vector<ArcId>>(sides_.size());
  for (ArcId a : ids<ArcId>(arcs_.size())) {
    for (PatchId p : arcs_[a].patch) {
      auto& list = patch_arcs_[p];
      if (list.empty() || list.back() != a) list.push_back(a);
    }
  }
  for (auto& list : patch_arcs_) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  finalized_ = true;
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
int CellComplex<D>::max_winding_number() const {
  int best = 0;
  for (int w : winding_) best = std::max(best, w);
  return best;
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
std::array<std::array<PatchId, 2>, 2> CellComplex<D>::topological_neighbors(ArcId a) const {
  const ArcJunctions& j = arcs_[a];
  return {{{j.patch[0], j.patch[2]}, {j.patch[1], j.patch[3]}}};
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
std::vector<GeometricNeighbors> CellComplex<D>::geometric_neighbors() const {
  std::vector<GeometricNeighbors> out;
  for (ArcId a : ids<ArcId>(arcs_.size())) {
    const ArcJunctions& j = arcs_[a];
    for (int k = 0; k < 4; ++k) {
      const CellId c = region_cell_[j.wedge[k]];
      if (c.is_valid()) out.push_back({c, a, k, j.patch[k], j.patch[(k + 1) % 4]});
    }
  }
  return out;
}

template <int D>
  requires ImmersionDim<DimTraits<D>>
std::vector<ArcId> CellComplex<D>::self_touching_arcs(CellId c) const {
  std::vector<ArcId> out;
  const RegionId r = cell_region_[c];
  for (ArcId a : ids<ArcId>(arcs_.size())) {
    const auto& w = arcs_[a].wedge;
    if (std::count(w.begin(), w.end(), r) >= 2) out.push_back(a);
  }
  return out;
}

}  // namespace imm
