// Text helpers of dim3's readers and writers (dim3/surface_io.cpp, dim3/tet_io.cpp): the
// dimension-free ones of core/text_io.h and those for 3D points. Internal to those two files.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "core/text_io.h"
#include "dim3/surface.h"

namespace imm::dim3::text {

using namespace imm::text;  // NOLINT(google-build-using-namespace): one set of text helpers

/// "x y z" with format_number: a vertex line of every text format written here.
inline std::string format_xyz(const Point3& p) {
  return format_number(p[0]) + ' ' + format_number(p[1]) + ' ' + format_number(p[2]);
}

/// The coordinates of a point for Defect::points.
inline std::vector<double> coordinates(const Point3& p) { return {p[0], p[1], p[2]}; }

inline bool is_finite(const Point3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

}  // namespace imm::dim3::text
