// The exact kernel of dim2/ (CGAL Epeck). Included only by dim2 translation units.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include "core/rational.h"
#include "dim2/curves.h"

namespace imm::dim2 {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using Point_2 = Kernel::Point_2;
using Segment_2 = Kernel::Segment_2;
using Triangle_2 = Kernel::Triangle_2;

/// Exact conversion (doubles are rationals).
inline Point_2 to_exact(const Point& p) { return Point_2(p.x, p.y); }
/// Rounding: output and display only.
inline Point to_double(const Point_2& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }
/// The exact value of an Epeck number as a GMP rational (CGAL is built WITH_GMPXX).
inline Rational to_rational(const FT& x) { return Rational(CGAL::exact(x)); }

}  // namespace imm::dim2
