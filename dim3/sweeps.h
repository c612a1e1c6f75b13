// The building blocks of the procedural surfaces (dim3/generators3.h): 3-vector maths on
// doubles, small rigid motions, and SWEEPS: rings of `sides` vertices around a centreline,
// joined ring to ring by quads split into two triangles, either closed into a torus or capped
// (a rounded cap: kCapRings rings on a quarter circle, then a pole). Surfaces of revolution
// are sweeps whose rings are the parallels of a profile curve. A capped or closed sweep with
// `rings` rings (cap rings included) has exactly 2 * sides * rings triangles.
//
// Doubles only: these build inputs, the exact predicates come after (check_generic_surface,
// the refinement). CGAL-free.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <numbers>
#include <vector>

#include "dim3/surface.h"

namespace imm::dim3::sweep {

constexpr double kPi = std::numbers::pi;
constexpr int kCapRings = 3;  ///< rings of a rounded cap (then the pole)

// ---- vectors -----------------------------------------------------------------------------------

inline Point3 plus(const Point3& a, const Point3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Point3 minus(const Point3& a, const Point3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Point3 times(double s, const Point3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Point3& a, const Point3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Point3 cross(const Point3& a, const Point3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double length(const Point3& a) { return std::sqrt(dot(a, a)); }
inline Point3 normalized(const Point3& a) { return times(1.0 / length(a), a); }

// ---- rigid motions -----------------------------------------------------------------------------

/// x -> rotation * x + shift.
struct Motion {
  std::array<Point3, 3> rows{Point3{1, 0, 0}, Point3{0, 1, 0}, Point3{0, 0, 1}};
  Point3 shift{0, 0, 0};
  [[nodiscard]] Point3 apply(const Point3& p) const {
    return {dot(rows[0], p) + shift[0], dot(rows[1], p) + shift[1], dot(rows[2], p) + shift[2]};
  }
};

/// Rotation by `angle` about `axis` (Rodrigues), then the shift.
Motion rotation(const Point3& axis, double angle, const Point3& shift = {0, 0, 0});

/// The small "odd" motion given to component `k` of a shape: a rotation by a few hundredths of
/// a radian about an irrational axis and a shift of a few thousandths. Visually nothing, but it
/// breaks every symmetry of the construction (mirror planes, equal sample angles) that could
/// put a vertex exactly on another sheet. The rotation is about `about` (the component's own
/// centre), so the component stays where the construction put it.
Motion odd_motion(int k, const Point3& about = {0, 0, 0});

/// Appends `part` moved by `motion`.
void append(Surface& out, const Surface& part, const Motion& motion);

/// `part` moved by `motion` (every triangle its own source face).
Surface moved(const Surface& part, const Motion& motion);

// ---- sweeps ------------------------------------------------------------------------------------

/// A ring of a sweep: `sides` points centre + radius (cos phi u + sin phi v), phi = phase +
/// 2 pi j / sides. (u, v) is an orthonormal pair; the sweep advances along u x v.
struct Ring {
  Point3 centre;
  Point3 u;
  Point3 v;
  double radius = 1.0;
  double phase = 0.0;
};

/// Radius factor of the ring point at angle phi of ring `ring` (1 when absent).
using RadiusScale = std::function<double(std::size_t ring, double phi)>;

/// Ring `index` starts half a step later every other ring (staggered rings: near-equilateral
/// triangles) plus an irrational jitter below a tenth of a step, so that no two rings of
/// different parts of a shape share their sample angles exactly.
double staggered_phase(std::size_t index, int sides);

/// A ring around `centre` perpendicular to `tangent`, with u the part of `reference`
/// perpendicular to the tangent. @pre reference is not parallel to tangent.
Ring ring_at(const Point3& centre, const Point3& tangent, const Point3& reference, double radius,
             double phase);

/// The ring of a surface of revolution around the z axis: profile point (rho, z).
Ring revolution_ring(double rho, double z, double phase);

/// Point j of the ring, its radius scaled by `scale`.
Point3 ring_point(const Ring& ring, int j, int sides, double scale);

/// The direction the sweep advances in at this ring (u x v).
inline Point3 ring_tangent(const Ring& r) { return cross(r.u, r.v); }

/// Vertices of the rings, then the bands between consecutive rings: quad (i, j), (i, j + 1),
/// (i + 1, j + 1), (i + 1, j) as two triangles split along its shorter diagonal. With the sweep
/// advancing along u x v, their normals point away from the centreline (outward); for a surface
/// of revolution the same holds when the profile runs counter-clockwise in the (rho, z) half
/// plane. No source_face yet.
Surface sweep_bands(const std::vector<Ring>& rings, int sides, bool closed,
                    const RadiusScale& scale);

/// A closed sweep (a torus-like tube). 2 * sides * rings triangles.
Surface closed_sweep(const std::vector<Ring>& rings, int sides, const RadiusScale& scale = {});

/// A sweep closed by a pole vertex before the first ring and one after the last.
/// 2 * sides * rings triangles.
Surface capped_sweep(const std::vector<Ring>& rings, int sides, const Point3& start_pole,
                     const Point3& end_pole);

/// Ring k (1 .. kCapRings, from the end outwards) of a rounded cap beyond the end ring `end`:
/// on the quarter circle of the end's radius, towards the unit vector `outward`.
Ring cap_ring(const Ring& end, const Point3& outward, int k, double phase);

/// A tube along the body rings with rounded caps: kCapRings rings on a quarter circle at each
/// end, then the pole. The phases continue the staggering of the body.
Surface round_capped_tube(const std::vector<Ring>& body, int sides);

/// A straight capped cylinder from a to b (radius r, `body_rings` >= 2 rings along it).
Surface cylinder(const Point3& a, const Point3& b, double radius, int sides, int body_rings,
                 const Point3& reference);

// ---- surfaces of revolution --------------------------------------------------------------------

/// The unit sphere: n - 1 parallels of 2 n sides and two poles (4 n (n - 1) triangles).
Surface unit_sphere(int n);

/// A closed profile curve (rho(s), z(s)), s in [0, 1), counter-clockwise, revolved about z:
/// `samples` rings of `sides` vertices.
Surface revolve_closed(const std::function<std::array<double, 2>(double)>& profile, int samples,
                       int sides);

/// The torus of revolution about z with radii `major` > `minor` (tube circle counter-clockwise
/// in the (rho, z) half plane): `samples` rings of `sides` vertices.
Surface ring_torus(double major, double minor, int samples, int sides);

}  // namespace imm::dim3::sweep
