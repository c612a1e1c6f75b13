// Per-dimension facts the dimension-generic core may name. The core never branches on the
// dimension: whatever differs between 2D and 3D lives here or in dim2/ and dim3/.
//
// The CGAL point and element types of each dimension live in dim2/kernel.h and dim3/kernel.h, not
// here, so that core/ compiles without the (slow) exact-kernel headers.
#pragma once

#include <array>
#include <concepts>
#include <string_view>

#include "core/ids.h"

namespace imm {

template <int D>
struct DimTraits;

/// d = 2: the input is a set of closed polygons, facets are segments, elements are triangles.
template <>
struct DimTraits<2> {
  static constexpr int kDim = 2;
  using FacetVerts = std::array<VertexId, 2>;
  using ElementVerts = std::array<VertexId, 3>;
  static constexpr std::string_view kFacetName = "segment";
  static constexpr std::string_view kElementName = "triangle";
  static constexpr std::string_view kMeasureName = "area";
};

/// d = 3: the input is a closed triangle mesh, facets are triangles, elements are tetrahedra.
template <>
struct DimTraits<3> {
  static constexpr int kDim = 3;
  using FacetVerts = std::array<VertexId, 3>;
  using ElementVerts = std::array<VertexId, 4>;
  static constexpr std::string_view kFacetName = "triangle";
  static constexpr std::string_view kElementName = "tetrahedron";
  static constexpr std::string_view kMeasureName = "volume";
};

/// The interface the core relies on.
template <class T>
concept ImmersionDim = requires {
  { T::kDim } -> std::convertible_to<int>;
  typename T::FacetVerts;
  typename T::ElementVerts;
  requires std::tuple_size_v<typename T::FacetVerts> == T::kDim;
  requires std::tuple_size_v<typename T::ElementVerts> == T::kDim + 1;
};

static_assert(ImmersionDim<DimTraits<2>>);
static_assert(ImmersionDim<DimTraits<3>>);

}  // namespace imm
