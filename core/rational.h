// Exact rationals for measures (areas, volumes) reported by the cell complex. This is the same
// GMP type CGAL's Epeck uses underneath (CGAL is configured WITH_GMPXX), so dim2/ and dim3/ hand
// exact values over without rounding.
#pragma once

#include <gmpxx.h>

#include <string>

namespace imm {

using Rational = mpq_class;

/// "p/q" in lowest terms (or "p" when q = 1).
inline std::string to_string(const Rational& q) { return q.get_str(); }

/// Rounded to the nearest double: for display and reports only, never for decisions.
inline double to_double(const Rational& q) { return q.get_d(); }

}  // namespace imm
