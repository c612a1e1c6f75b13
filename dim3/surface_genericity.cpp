#include "dim3/surface_genericity.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <array>
#include <string>

#include "dim3/triangle_pairs.h"

namespace imm::dim3 {

namespace {

using IK = CGAL::Exact_predicates_inexact_constructions_kernel;
using IPoint = IK::Point_3;

class GenericityCheck {
 public:
  GenericityCheck(const Surface& s, bool keep) : s_(s), keep_(keep) {
    points_.reserve(s.vertices.size());
    for (const Point3& p : s.vertices) points_.emplace_back(p[0], p[1], p[2]);
  }

  SurfaceGenericity run() {
    for (const auto& [a, b] : overlapping_triangle_pairs(s_)) {
      classify(a, b);
      if (!result_.generic) break;
    }
    return std::move(result_);
  }

 private:
  const IPoint& p(std::uint32_t t, int k) const { return points_[s_.triangles[t][k]]; }
  IK::Triangle_3 triangle(std::uint32_t t) const { return {p(t, 0), p(t, 1), p(t, 2)}; }

  void fail(std::uint32_t a, std::uint32_t b, const std::string& what) {
    result_.generic = false;
    result_.problem = "triangles " + std::to_string(a) + " and " + std::to_string(b) + ": " + what;
  }

  void classify(std::uint32_t a, std::uint32_t b) {
    const Triangle& ta = s_.triangles[a];
    const Triangle& tb = s_.triangles[b];
    std::array<int, 3> match{-1, -1, -1};  // corner of b equal to corner k of a
    int shared = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (ta[i] == tb[j]) {
          match[i] = j;
          ++shared;
        }
    if (shared == 3) return fail(a, b, "the same three vertices");
    if (shared == 2) {
      int oa = 0;
      while (match[oa] >= 0) ++oa;
      int ob = 0;
      while (tb[ob] == ta[0] || tb[ob] == ta[1] || tb[ob] == ta[2]) ++ob;
      const IPoint &u = p(a, (oa + 1) % 3), &v = p(a, (oa + 2) % 3);
      if (CGAL::orientation(u, v, p(a, oa), p(b, ob)) == CGAL::COPLANAR &&
          CGAL::coplanar_orientation(u, v, p(a, oa), p(b, ob)) == CGAL::POSITIVE) {
        fail(a, b, "share an edge and fold onto each other");
      }
      return;
    }
    if (shared == 1) {
      int ia = 0;
      while (match[ia] < 0) ++ia;
      const int ib = match[ia];
      const IK::Segment_3 far_a(p(a, (ia + 1) % 3), p(a, (ia + 2) % 3));
      const IK::Segment_3 far_b(p(b, (ib + 1) % 3), p(b, (ib + 2) % 3));
      if (CGAL::do_intersect(far_a, triangle(b)) || CGAL::do_intersect(far_b, triangle(a)))
        fail(a, b, "share one vertex and meet beyond it");
      return;
    }
    std::array<CGAL::Orientation, 3> oa{}, ob{};
    bool zero = false;
    for (int k = 0; k < 3; ++k) {
      oa[k] = CGAL::orientation(p(b, 0), p(b, 1), p(b, 2), p(a, k));
      ob[k] = CGAL::orientation(p(a, 0), p(a, 1), p(a, 2), p(b, k));
      zero = zero || oa[k] == CGAL::COPLANAR || ob[k] == CGAL::COPLANAR;
    }
    auto one_side = [](const std::array<CGAL::Orientation, 3>& o) {
      return o[0] == o[1] && o[1] == o[2] && o[0] != CGAL::COPLANAR;
    };
    if (one_side(oa) || one_side(ob)) return;
    if (!CGAL::do_intersect(triangle(a), triangle(b))) return;
    if (zero)
      return fail(a, b, "a vertex lies exactly in the other triangle's plane where they meet");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const IPoint &a0 = p(a, i), &a1 = p(a, (i + 1) % 3), &b0 = p(b, j), &b1 = p(b, (j + 1) % 3);
        if (CGAL::orientation(a0, a1, b0, b1) == CGAL::COPLANAR &&
            CGAL::do_intersect(IK::Segment_3(a0, a1), IK::Segment_3(b0, b1))) {
          return fail(a, b, "an edge of one meets an edge of the other");
        }
      }
    ++result_.intersecting_pairs;
    if (keep_) result_.pairs.emplace_back(a, b);
  }

  const Surface& s_;
  bool keep_;
  std::vector<IPoint> points_;
  SurfaceGenericity result_;
};

}  // namespace

SurfaceGenericity check_generic_surface(const Surface& surface, bool keep_pairs) {
  return GenericityCheck(surface, keep_pairs).run();
}

}  // namespace imm::dim3
