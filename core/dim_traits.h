// What differs between the dimensions and the dimension-generic code needs to name. The core
// never branches on the dimension: whatever differs between 2D and 3D lives here or in dim2/
// and dim3/. Element arity is D + 1 and facet arity D, written as such where needed.
//
// The CGAL point and element types of each dimension live in dim2/kernel.h and dim3/ (the exact
// kernel), not here, so that core/ compiles without the (slow) exact-kernel headers.
#pragma once

#include <concepts>
#include <string_view>

namespace imm {

template <int D>
struct DimTraits;

/// d = 2: the input is a set of closed polygons, the elements are triangles.
template <>
struct DimTraits<2> {
  static constexpr int kDim = 2;
  static constexpr std::string_view kElementName = "triangle";  ///< in messages
  static constexpr std::string_view kMeditElements = "Triangles";  ///< core/medit.h section
};

/// d = 3: the input is a closed triangle mesh, the elements are tetrahedra.
template <>
struct DimTraits<3> {
  static constexpr int kDim = 3;
  static constexpr std::string_view kElementName = "tet";
  static constexpr std::string_view kMeditElements = "Tetrahedra";
};

/// The dimensions the library is built for (core/instantiate.cpp instantiates both).
template <class T>
concept ImmersionDim = requires {
  { T::kDim } -> std::convertible_to<int>;
  { T::kElementName } -> std::convertible_to<std::string_view>;
  { T::kMeditElements } -> std::convertible_to<std::string_view>;
};

static_assert(ImmersionDim<DimTraits<2>>);
static_assert(ImmersionDim<DimTraits<3>>);

}  // namespace imm
