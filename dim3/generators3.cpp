#include "dim3/generators3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <unordered_map>

#include "core/diagnostics.h"
#include "dim3/sweeps.h"

namespace imm::dim3 {

using namespace sweep;  // NOLINT(google-build-using-namespace): the shapes are built from sweeps

namespace {

// ---- seeded randomness (splitmix64: the same numbers on every platform) ----------------------

class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }
  /// Uniform on the unit sphere.
  Point3 direction() {
    const double z = uniform(-1, 1), a = uniform(0, 2 * kPi), s = std::sqrt(1 - z * z);
    return {s * std::cos(a), s * std::sin(a), z};
  }

 private:
  std::uint64_t state_;
};

/// Draws until `make` returns a generic surface (a degenerate draw is replaced by the next draw
/// of the same stream; not seen in practice).
Surface first_generic(std::uint64_t seed, const std::function<Surface(Random&)>& make) {
  Random random(seed);
  for (int attempt = 0; attempt < 100; ++attempt) {
    Surface s = make(random);
    if (check_generic_surface(s).generic) return s;
  }
  IMM_ASSERT(false,
             "no generic random surface after 100 draws (seed " + std::to_string(seed) + ")");
  return {};
}

// ---- the head and the mouth ----------------------------------------------------------------

/// One sweep: head sphere (radius 1, rings perpendicular to x), lip of radius 0.15 forward,
/// down round a bend of radius 0.3, back towards the chin at z = -0.6 up to x = tip_x, then a
/// rounded tip.
Surface head_sweep(int n, double tip_x) {
  constexpr double kLip = 0.15, kBend = 0.3, kFront = 1.35;
  const int sides = n;
  const int head_rings = n / 2;
  const double theta_end = kPi - std::asin(kLip);
  const Point3 across{0, 1, 0};  // u of every ring: the centreline lies in the xz plane
  std::vector<Ring> rings;
  std::size_t index = 0;
  for (int k = 1; k <= head_rings; ++k) {
    const double theta = theta_end * k / head_rings;
    rings.push_back(ring_at({-std::cos(theta), 0, 0}, {1, 0, 0}, across, std::sin(theta),
                            staggered_phase(index++, sides)));
  }
  // The lip, sampled by arc length: straight, half circle, straight back.
  const double x0 = std::cos(std::asin(kLip));
  const double l1 = kFront - x0, l2 = kPi * kBend, l3 = kFront - tip_x;
  const double total = l1 + l2 + l3;
  const int lip_rings = n;
  for (int k = 1; k <= lip_rings; ++k) {
    const double s = total * k / lip_rings;
    Point3 c, t;
    if (s <= l1) {
      c = {x0 + s, 0, 0};
      t = {1, 0, 0};
    } else if (s <= l1 + l2) {
      const double beta = (s - l1) / kBend;
      c = {kFront + kBend * std::sin(beta), 0, -kBend + kBend * std::cos(beta)};
      t = {std::cos(beta), 0, -std::sin(beta)};
    } else {
      c = {kFront - (s - l1 - l2), 0, -2 * kBend};
      t = {-1, 0, 0};
    }
    rings.push_back(ring_at(c, t, across, kLip, staggered_phase(index++, sides)));
  }
  const Ring tip = rings.back();
  const Point3 t1 = ring_tangent(tip);
  for (int k = 1; k <= kCapRings; ++k)
    rings.push_back(cap_ring(tip, t1, k, staggered_phase(index++, sides)));
  Surface s = capped_sweep(rings, sides, {-1, 0, 0}, plus(tip.centre, times(kLip, t1)));
  Surface out;
  append(out, s, odd_motion(0));
  return out;
}

// ---- the tree --------------------------------------------------------------------------------

/// Branches closer than kMargin * (sum of radii) count as touching.
constexpr double kMargin = 1.1;

struct Capsule {
  Point3 a, b;
  double radius;
  int parent;
};

/// Distance between segments [p0, p1] and [q0, q1] (clamped closest points).
double segment_distance(const Point3& p0, const Point3& p1, const Point3& q0, const Point3& q1) {
  const Point3 d1 = minus(p1, p0), d2 = minus(q1, q0), r = minus(p0, q0);
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  const double c = dot(d1, r), b = dot(d1, d2), denom = a * e - b * b;
  double s = denom > 1e-300 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return length(minus(plus(p0, times(s, d1)), plus(q0, times(t, d2))));
}

/// Uniform grid over capsule bounding boxes, for the "touches another branch" test.
class CapsuleGrid {
 public:
  explicit CapsuleGrid(double cell) : cell_(cell) {}
  void insert(const Capsule& c, int id) {
    for_cells(c, [&](std::int64_t key) { cells_[key].push_back(id); });
  }
  /// Calls `visit(id)` for every capsule sharing a grid cell with c (an id may repeat).
  template <class Visit>
  void query(const Capsule& c, Visit&& visit) const {
    for_cells(c, [&](std::int64_t key) {
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (int id : it->second) visit(id);
    });
  }

 private:
  template <class F>
  void for_cells(const Capsule& c, F&& f) const {
    std::array<std::int64_t, 3> lo{}, hi{};
    for (int d = 0; d < 3; ++d) {
      // boxes grown by the margin (1.1 radius): capsules closer than the margin share a cell
      lo[d] = static_cast<std::int64_t>(
          std::floor((std::min(c.a[d], c.b[d]) - kMargin * c.radius) / cell_));
      hi[d] = static_cast<std::int64_t>(
          std::floor((std::max(c.a[d], c.b[d]) + kMargin * c.radius) / cell_));
    }
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
          f(((x + (1 << 20)) << 42) ^ ((y + (1 << 20)) << 21) ^ (z + (1 << 20)));
  }
  double cell_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
};

/// The branches of the tree (trunk first, breadth first).
std::vector<Capsule> tree_capsules(int branches, std::uint64_t seed) {
  constexpr double kTrunkRadius = 0.1, kTrunkLength = 1.4;
  constexpr double kLengthRatio = 0.8, kRadiusRatio = 0.68;
  Random random(seed);
  std::vector<Capsule> out;
  out.push_back({{0, 0, 0}, {0.013, -0.007, kTrunkLength}, kTrunkRadius, -1});
  CapsuleGrid grid(0.08);
  grid.insert(out.front(), 0);
  std::vector<int> stamp(1, -1);  // last query that looked at each capsule
  int query = 0;
  for (std::size_t next = 0; next < out.size() && static_cast<int>(out.size()) < branches; ++next) {
    const Capsule parent = out[next];
    const Point3 axis = minus(parent.b, parent.a);
    const double parent_length = length(axis);
    const Point3 t = times(1.0 / parent_length, axis);
    const Point3 helper = std::abs(t[0]) < 0.9 ? Point3{1, 0, 0} : Point3{0, 1, 0};
    const Point3 e1 = normalized(cross(t, helper)), e2 = cross(t, e1);
    for (int child = 0; child < 3 && static_cast<int>(out.size()) < branches; ++child) {
      for (int attempt = 0; attempt < 12; ++attempt) {
        const double f = random.uniform(0.35, 0.7);
        const double tilt = random.uniform(35, 65) * kPi / 180;
        const double azimuth = 2 * kPi * (child + random.uniform(0.1, 0.9)) / 3;
        // Bent upwards (tropism), but kept 32-70 degrees off the parent's axis so that the
        // child leaves through the parent's side wall well before the parent's end.
        const Point3 dir =
            normalized(plus(plus(times(std::cos(tilt), t),
                                 times(std::sin(tilt), plus(times(std::cos(azimuth), e1),
                                                            times(std::sin(azimuth), e2)))),
                            Point3{0, 0, 0.4}));
        const double off_axis = std::acos(std::clamp(dot(dir, t), -1.0, 1.0)) * 180 / kPi;
        if (off_axis < 32 || off_axis > 70) continue;
        const Point3 root = plus(parent.a, times(f * parent_length, t));
        const Capsule candidate{root, plus(root, times(kLengthRatio * parent_length, dir)),
                                kRadiusRatio * parent.radius, static_cast<int>(next)};
        bool free = true;
        const int me = static_cast<int>(out.size());
        ++query;
        grid.query(candidate, [&](int other) {
          if (!free || other == candidate.parent || stamp[static_cast<std::size_t>(other)] == query)
            return;
          stamp[static_cast<std::size_t>(other)] = query;
          const Capsule& o = out[static_cast<std::size_t>(other)];
          if (segment_distance(candidate.a, candidate.b, o.a, o.b) <
              kMargin * (candidate.radius + o.radius)) {
            free = false;
          }
        });
        if (!free) continue;
        out.push_back(candidate);
        stamp.push_back(-1);
        grid.insert(candidate, me);
        break;
      }
    }
  }
  return out;
}

}  // namespace

// ---- embedded controls -------------------------------------------------------------------------

Surface folded_bipyramid(int percent) {
  IMM_ASSERT(percent >= 0, "folded_bipyramid needs percent >= 0");
  Surface s;
  const double ring[6][3] = {{4, 0, 0.5}, {2, 3, -0.5}, {-2, 3, 0.5}, {-4, 0, -0.5}, {-2, -3, 0.5}, {2, -3, -0.5}};
  for (const auto& r : ring) s.vertices.push_back({r[0], r[1], r[2]});
  const double t = percent / 100.0;
  s.vertices.push_back({-5.5 * t, -3 * t, 4 - 3 * t});  // the top vertex: (0, 0, 4) to (-5.5, -3, 1)
  s.vertices.push_back({0, 0, -4});                      // the bottom vertex
  for (std::uint32_t k = 0; k < 6; ++k) {
    s.triangles.push_back({k, (k + 1) % 6, 6});
    s.triangles.push_back({(k + 1) % 6, k, 7});
  }
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) s.source_face.push_back(t);
  return s;
}

Surface sphere(int n) {
  IMM_ASSERT(n >= 3, "sphere needs n >= 3");
  return moved(unit_sphere(n), odd_motion(0));
}

Surface torus(int n) {
  IMM_ASSERT(n >= 6, "torus needs n >= 6");
  return moved(ring_torus(1, 0.4, n / 2, n), odd_motion(0));
}

Surface two_spheres(int n) {
  IMM_ASSERT(n >= 3, "two_spheres needs n >= 3");
  Surface out;
  append(out, unit_sphere(n), odd_motion(0));
  Surface small = unit_sphere(n);
  for (Point3& p : small.vertices) p = times(0.85, p);
  Motion m = odd_motion(1);
  m.shift = plus(m.shift, Point3{1.15, 0.07, 0.04});
  append(out, small, m);  // turned about its own centre, then moved there
  return out;
}

/// Two overlapping tori as one input (the input class of the CSG reference measurement quoted
/// in the Table 2 issue: "two overlapping tori, 4,096 triangles"). Both have major radius 1,
/// minor radius 0.4 and axis z, each revolved from `n` profile samples with `n` ring sides
/// (2 n^2 triangles each, 4 n^2 in all: n = 32 gives 4,096). The second one's centre is moved
/// by (1, 0.07, kLift) and turned by odd_motion(1) about it. Its core circle then crosses the
/// first one's twice (near (0.5, +-0.87), at about 60 degrees, one core kLift above the other),
/// and nowhere else do the tubes meet: the solid tori's planar shadows (annuli 0.6 <= rho <= 1.4
/// about centres 1 apart) overlap only in two lenses around those crossings.
///
/// Counts. At each crossing the two tubes are like two equal round cylinders whose axes pass
/// kLift = 0.15 apart (0 < kLift < 0.8 = the sum of the radii, and the lift keeps the tubes'
/// tops and bottoms, where equal cylinders with meeting axes would touch, well apart): each
/// bites into the other without cutting through it, so the intersection of the solids there is
/// one ball bounded by one disk of each torus, and the two surfaces meet in ONE closed loop
/// per crossing. Regions: the outside (winding 0; the holes of both tori open upwards, so the
/// complement of the solids is connected), each solid torus minus the other (1 each; still a
/// connected solid torus, as the bite leaves a crescent of the tube below it) and the two
/// balls (2 each): 5 regions, 4 cells, windings 0..2. Patches: each torus is cut by its two
/// loops into the two disks inside the other and the rest (a torus minus two disks): 6.
/// Arcs: 2 closed loops, no triple points. Immersions: a winding-2 ball has two boundary
/// patches, so of its two layers one ends at each and the gluing is forced: 1 immersion (the
/// two solid tori).
///
/// The argument is about the smooth shape; the meshes keep it at every size allowed: `immerse
/// cells` finds these counts, generic, for every n from 3 (triangular tubes, 36 triangles) to
/// 128 and at 200, 256, 384, 512, 700 and 1000 (the registry's maximum), and the tests build the
/// complex and run the search at several n.
Surface two_tori(int n) {
  IMM_ASSERT(n >= 3, "two_tori needs n >= 3");
  constexpr double kLift = 0.15;
  const Surface tube = ring_torus(1, 0.4, n, n);
  Surface out;
  append(out, tube, odd_motion(0));
  Motion m = odd_motion(1);
  m.shift = plus(m.shift, Point3{1.0, 0.07, kLift});
  append(out, tube, m);  // turned about its own centre, then moved there
  return out;
}


// ---- the paper's figures -------------------------------------------------------------------

Surface tube_overlap(int sides) {
  IMM_ASSERT(sides >= 6, "tube_overlap needs sides >= 6");
  // Prolate trochoid (b = 2): self-crossing at u = +-u*, u* = 2 sin u* (1.8955); rising so that
  // the upper strand passes 0.3 above the lower one there.
  const double lift = 0.3 / (2 * 1.895494267033981);
  const int samples = 6 * sides + 1;
  std::vector<Ring> body;
  for (int i = 0; i < samples; ++i) {
    const double u = -3 + 6.0 * i / (samples - 1);
    body.push_back(ring_at({u - 2 * std::sin(u), 1 - 2 * std::cos(u), lift * u},
                           {1 - 2 * std::cos(u), 2 * std::sin(u), lift}, {0, 0, 1}, 0.3, 0.0));
  }
  Surface out;
  append(out, round_capped_tube(body, sides), odd_motion(0));
  return out;
}

Surface helix(int loops, int sides) {
  IMM_ASSERT(loops >= 1 && sides >= 6 && sides % 2 == 0, "helix needs loops >= 1, even sides >= 6");
  constexpr double kPitch = 0.4, kTube = 0.3;
  const int per_loop = 5 * sides / 2;
  const int samples = per_loop * loops + 1;
  std::vector<Ring> body;
  body.reserve(static_cast<std::size_t>(samples));
  for (int i = 0; i < samples; ++i) {
    const double t = 2 * kPi * i / per_loop;
    const double c = std::cos(t), s = std::sin(t);
    body.push_back(ring_at({c, s, kPitch * t / (2 * kPi)}, {-s, c, kPitch / (2 * kPi)}, {-c, -s, 0},
                           kTube, 0.0));
  }
  Surface out;
  append(out, round_capped_tube(body, sides), odd_motion(0));
  return out;
}

Surface double_loop_torus(int n) {
  IMM_ASSERT(n >= 8, "double_loop_torus needs n >= 8");
  constexpr double kA = 0.22, kB = 0.15, kTube = 0.3;
  const int sides = n / 2;
  std::vector<Ring> rings;
  for (int i = 0; i < 2 * n; ++i) {
    const double t = 2 * kPi * (i + 0.25) / n;  // t in [0, 4 pi): two turns
    const double rho = 1 + kA * std::cos(t / 2), drho = -0.5 * kA * std::sin(t / 2);
    const Point3 c{rho * std::cos(t), rho * std::sin(t), kB * std::sin(t / 2)};
    const Point3 d{drho * std::cos(t) - rho * std::sin(t), drho * std::sin(t) + rho * std::cos(t),
                   0.5 * kB * std::cos(t / 2)};
    rings.push_back(
        ring_at(c, d, {0, 0, 1}, kTube, staggered_phase(static_cast<std::size_t>(i), sides)));
  }
  Surface out;
  append(out, closed_sweep(rings, sides), odd_motion(0));
  return out;
}

Surface sacht_torus(int n, bool large) {
  IMM_ASSERT(n >= 12, "sacht_torus needs n >= 12");
  Surface out = moved(ring_torus(1, 0.35, n / 2, n), odd_motion(0));
  const int sides = std::max(6, n / 3);
  const int through = large ? 8 : 4;
  for (int k = 0; k < through; ++k) {
    const double angle = 2 * kPi * k / through + 0.1234 + 0.0371 * k;
    const double rho = 1 + 0.021 * (k % 3 - 1) + 0.0057;
    const Point3 centre{rho * std::cos(angle), rho * std::sin(angle), 0.0113 * k - 0.02};
    const Point3 axis =
        normalized({0.031 * std::sin(1.7 * k + 0.3), 0.027 * std::cos(2.3 * k + 0.1), 1});
    const double radius = 0.12 + 0.004 * k;
    append(out,
           cylinder(minus(centre, times(0.75, axis)), plus(centre, times(0.75, axis)), radius,
                    sides, 3, {1, 0, 0}),
           odd_motion(k + 1, centre));
  }
  if (large) {
    for (int k = 0; k < 4; ++k) {
      const double angle = 2 * kPi * (k + 0.5) / 4 + 0.2 + 0.03 * k;
      const double rho = 1.33 + 0.003 * k;
      const Point3 centre{rho * std::cos(angle), rho * std::sin(angle), 0.017 * k - 0.03};
      const Point3 axis =
          normalized({0.021 * std::cos(1.3 * k), 0.033 * std::sin(0.7 * k + 0.5), 1});
      append(out,
             cylinder(minus(centre, times(0.7, axis)), plus(centre, times(0.7, axis)), 0.1, sides,
                      3, {1, 0, 0}),
             odd_motion(through + k + 1, centre));
    }
  }
  return out;
}

Surface quintuple_torus(int n) {
  IMM_ASSERT(n >= 8, "quintuple_torus needs n >= 8");
  Surface out;
  const Surface tube = ring_torus(1, 0.3, n / 2, n);
  std::array<double, 5> angles{};
  for (int k = 0; k < 5; ++k) {
    angles[static_cast<std::size_t>(k)] = 2 * kPi * k / 5 + 0.05 + 0.013 * k;
    const double a = angles[static_cast<std::size_t>(k)];
    Motion m = rotation({0.3 * std::sin(2.1 * k + 0.4), 0.3 * std::cos(1.3 * k), 1}, 0.7 * k + 0.11,
                        {2 * std::cos(a), 2 * std::sin(a), 0.01 * k - 0.02});
    // a slight tilt of each torus, about a horizontal axis
    const Motion tilt = rotation({std::cos(1.9 * k), std::sin(1.9 * k), 0}, 0.02 + 0.013 * k);
    append(out, moved(tube, tilt), m);
  }
  const int sides = std::max(6, n / 2);
  const int body = std::max(3, 2 * n / 3);
  for (int k = 0; k < 5; ++k) {
    const double a = angles[static_cast<std::size_t>(k)];
    const Point3 dir =
        normalized({std::cos(a), std::sin(a), 0.04 * (k % 2 == 0 ? 1 : -1) + 0.007 * k});
    const Point3 centre{0.006 * k - 0.012, 0.011 - 0.004 * k, 0.005 * k - 0.01};
    append(out,
           cylinder(minus(centre, times(3.6, dir)), plus(centre, times(3.6, dir)), 0.16, sides,
                    body, {0, 0, 1}),
           odd_motion(k + 1));
  }
  const std::array<std::array<double, 2>, 2> tilted{{{0.25, 1.1}, {0.4, 3.0}}};
  for (int k = 0; k < 2; ++k) {
    const auto [tilt, azimuth] = tilted[static_cast<std::size_t>(k)];
    const Point3 dir{std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                     std::cos(tilt)};
    const Point3 centre{0.009 - 0.017 * k, 0.008 * k - 0.013, 0.004 + 0.006 * k};
    append(out,
           cylinder(minus(centre, times(1.6, dir)), plus(centre, times(1.6, dir)), 0.16, sides,
                    body, {1, 0, 0}),
           odd_motion(k + 6));
  }
  return out;
}

Surface tree(int branches, std::uint64_t seed) {
  IMM_ASSERT(branches >= 1, "tree needs branches >= 1");
  const std::vector<Capsule> capsules = tree_capsules(branches, seed);
  Surface out;
  out.vertices.reserve(capsules.size() * 62);
  out.triangles.reserve(capsules.size() * 120);
  out.source_face.reserve(capsules.size() * 120);
  const Motion identity;
  for (const Capsule& c : capsules) {
    const Point3 axis = minus(c.b, c.a);
    const Point3 reference =
        std::abs(axis[0]) < 0.9 * length(axis) ? Point3{1, 0, 0} : Point3{0, 1, 0};
    append(out, cylinder(c.a, c.b, c.radius, 6, 4, reference), identity);
  }
  return out;
}

Surface head(int n) {
  IMM_ASSERT(n >= 16, "head needs n >= 16");
  return head_sweep(n, 0.55);
}

// ---- Fig. 8 ----------------------------------------------------------------------------------

Surface limacon_torus(int n) {
  IMM_ASSERT(n >= 12, "limacon_torus needs n >= 12");
  const auto profile = [](double s) {
    const double theta = 2 * kPi * s, r = 1 + 2 * std::cos(theta);
    return std::array<double, 2>{1.2 + r * std::cos(theta), r * std::sin(theta)};
  };
  return moved(revolve_closed(profile, n, n), odd_motion(0));
}

Surface figure_eight_torus(int n) {
  IMM_ASSERT(n >= 12, "figure_eight_torus needs n >= 12");
  const auto profile = [](double s) {
    const double t = 2 * kPi * s;
    return std::array<double, 2>{1.5 + std::cos(t), std::sin(t) * std::cos(t)};
  };
  return moved(revolve_closed(profile, n, n), odd_motion(0));
}

Surface poke_through(int n) {
  IMM_ASSERT(n >= 8, "poke_through needs n >= 8");
  constexpr double kTunnel = 0.3, kTop = 1.4;
  const int sides = n;
  std::vector<Ring> rings;
  std::size_t index = 0;
  auto add = [&](double rho, double z) {
    rings.push_back(revolution_ring(rho, z, staggered_phase(index++, sides)));
  };
  // The tip cap: a quarter circle from the axis (the start pole) out and down to the wall.
  for (int k = 1; k <= kCapRings; ++k) {
    const double beta = (kPi / 2) * (1 - static_cast<double>(k) / (kCapRings + 1));
    add(kTunnel * std::cos(beta), kTop + kTunnel * std::sin(beta));
  }
  // The tunnel wall, downwards, to where it meets the unit sphere at the bottom.
  const double bottom = -std::sqrt(1 - kTunnel * kTunnel);
  const int wall = n / 2;
  for (int k = 0; k < wall; ++k) add(kTunnel, kTop - (kTop - bottom) * k / wall);
  // The sphere from that circle up over the equator towards the top pole.
  const double gamma0 = std::asin(kTunnel);
  for (int k = 0; k < n; ++k) {
    const double gamma = gamma0 + (kPi - gamma0) * k / n;
    add(std::sin(gamma), -std::cos(gamma));
  }
  Surface out;
  append(out, capped_sweep(rings, sides, {0, 0, kTop + kTunnel}, {0, 0, 1}), odd_motion(0));
  return out;
}

// ---- nearly self-intersecting ------------------------------------------------------------------

Surface comb(int teeth) {
  IMM_ASSERT(teeth >= 1, "comb needs teeth >= 1");
  constexpr double kWidth = 1, kGap = 1.0 / 64, kTooth = 6, kBar = 2, kDepth = 1;
  std::vector<double> xs;  // breakpoints: the teeth's left and right sides
  for (int i = 0; i < teeth; ++i) {
    xs.push_back(i * (kWidth + kGap));
    xs.push_back(i * (kWidth + kGap) + kWidth);
  }
  const int b = static_cast<int>(xs.size());
  // 2D vertices: bottom[k] = (x_k, -tooth), base[k] = (x_k, 0), top[k] = (x_k, bar).
  std::vector<std::array<double, 2>> points;
  auto bottom = [&](int k) { return k; };
  auto base = [&](int k) { return b + k; };
  auto top = [&](int k) { return 2 * b + k; };
  for (double x : xs) points.push_back({x, -kTooth});
  for (double x : xs) points.push_back({x, 0});
  for (double x : xs) points.push_back({x, kBar});
  // Counter-clockwise outline.
  std::vector<int> outline;
  for (int i = 0; i < teeth; ++i) {
    const int l = 2 * i, r = 2 * i + 1;
    if (i > 0) outline.push_back(base(l));
    outline.push_back(bottom(l));
    outline.push_back(bottom(r));
    outline.push_back(base(r));
  }
  for (int k = b - 1; k >= 0; --k) outline.push_back(top(k));
  outline.push_back(base(0));
  // Cap quads (counter-clockwise seen from +z): bar pieces and teeth.
  std::vector<std::array<int, 4>> quads;
  for (int k = 0; k + 1 < b; ++k) quads.push_back({base(k), base(k + 1), top(k + 1), top(k)});
  for (int i = 0; i < teeth; ++i)
    quads.push_back({bottom(2 * i), bottom(2 * i + 1), base(2 * i + 1), base(2 * i)});

  Surface s;
  const auto count = static_cast<std::uint32_t>(points.size());
  for (double z : {0.0, kDepth})
    for (const auto& p : points) s.vertices.push_back({p[0], p[1], z});
  auto lower = [](int v) { return static_cast<std::uint32_t>(v); };
  auto upper = [&](int v) { return static_cast<std::uint32_t>(v) + count; };
  for (std::size_t e = 0; e < outline.size(); ++e) {
    const int p = outline[e], q = outline[(e + 1) % outline.size()];
    s.triangles.push_back({lower(p), lower(q), upper(q)});
    s.triangles.push_back({lower(p), upper(q), upper(p)});
  }
  for (const auto& q : quads) {
    s.triangles.push_back({upper(q[0]), upper(q[1]), upper(q[2])});
    s.triangles.push_back({upper(q[0]), upper(q[2]), upper(q[3])});
    s.triangles.push_back({lower(q[0]), lower(q[2]), lower(q[1])});
    s.triangles.push_back({lower(q[0]), lower(q[3]), lower(q[2])});
  }
  s.source_face.resize(s.triangles.size());
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    s.source_face[t] = static_cast<std::uint32_t>(t);
  return s;
}

Surface mouth(int n) {
  IMM_ASSERT(n >= 16, "mouth needs n >= 16");
  // The lip's axis runs at z = -0.6; its capsule (radius 0.15) ends where it is 1.004 from the
  // head's centre.
  constexpr double kGap = 0.004;
  return head_sweep(n, std::sqrt((1.15 + kGap) * (1.15 + kGap) - 0.36));
}

// ---- seeded random inputs ---------------------------------------------------------------------

Surface random_blobs(int blobs, std::uint64_t seed, int n) {
  IMM_ASSERT(blobs >= 1 && n >= 4, "random_blobs needs blobs >= 1, n >= 4");
  const Surface base = unit_sphere(n);
  return first_generic(seed, [&](Random& random) {
    const double side = 1.6 * std::cbrt(static_cast<double>(blobs)) - 1.0;
    Surface out;
    for (int b = 0; b < blobs; ++b) {
      const Point3 axes{random.uniform(0.6, 1.2), random.uniform(0.6, 1.2),
                        random.uniform(0.6, 1.2)};
      std::array<Point3, 3> waves{};
      std::array<double, 3> amplitude{}, shift{};
      for (std::size_t m = 0; m < 3; ++m) {
        waves[m] = times(random.uniform(2, 3), random.direction());
        amplitude[m] = random.uniform(0, 0.05);
        shift[m] = random.uniform(0, 2 * kPi);
      }
      Surface blob = base;
      for (Point3& p : blob.vertices) {
        double f = 1;
        for (std::size_t m = 0; m < 3; ++m)
          f += amplitude[m] * std::sin(dot(waves[m], p) + shift[m]);
        p = {axes[0] * f * p[0], axes[1] * f * p[1], axes[2] * f * p[2]};
      }
      const Point3 centre{random.uniform(0, side), random.uniform(0, side),
                          random.uniform(0, side)};
      append(out, blob, rotation(random.direction(), random.uniform(0, 2 * kPi), centre));
    }
    return out;
  });
}

namespace {

/// `part` scaled by `scale` about the origin.
Surface scaled(Surface part, double scale) {
  for (Point3& p : part.vertices) p = times(scale, p);
  return part;
}

/// Appends `part` with a random rotation about the origin, then moved to a random centre in
/// [lo, hi) (per coordinate).
void append_randomly(Surface& out, const Surface& part, Random& random, const Point3& lo,
                     const Point3& hi) {
  const Point3 axis = random.direction();
  const double angle = random.uniform(0, 2 * kPi);
  const Point3 centre{random.uniform(lo[0], hi[0]), random.uniform(lo[1], hi[1]),
                      random.uniform(lo[2], hi[2])};
  append(out, part, rotation(axis, angle, centre));
}

}  // namespace

Surface spheres_pile(int count, std::uint64_t seed, int n) {
  IMM_ASSERT(count >= 1 && n >= 3, "spheres_pile needs count >= 1, n >= 3");
  const Surface ball = scaled(unit_sphere(n), 0.5);
  return first_generic(seed, [&](Random& random) {
    Surface out;
    for (int k = 0; k < count; ++k) append_randomly(out, ball, random, {0, 0, 0}, {0.6, 0.6, 0.6});
    return out;
  });
}

Surface tori_pile(int count, std::uint64_t seed, int n) {
  IMM_ASSERT(count >= 1 && n >= 6, "tori_pile needs count >= 1, n >= 6");
  const Surface ring = ring_torus(0.5, 0.18, n / 2, n);
  return first_generic(seed, [&](Random& random) {
    Surface out;
    for (int k = 0; k < count; ++k) append_randomly(out, ring, random, {0, 0, 0}, {0.6, 0.6, 0.6});
    return out;
  });
}

Surface helix_in_spheres(int count, std::uint64_t seed, int loops, int n) {
  IMM_ASSERT(count >= 0 && loops >= 1 && n >= 3, "helix_in_spheres needs loops >= 1, n >= 3");
  const Surface coil = helix(loops, 12);
  const Surface ball = scaled(unit_sphere(n), 0.5);
  return first_generic(seed, [&](Random& random) {
    Surface out = coil;
    for (int k = 0; k < count; ++k) {
      append_randomly(out, ball, random, {-1, -1, 0}, {1, 1, 0.4 * loops});
    }
    return out;
  });
}

Surface perturbed_torus(int n, std::uint64_t seed) {
  IMM_ASSERT(n >= 12, "perturbed_torus needs n >= 12");
  return first_generic(seed, [&](Random& random) {
    const double b = random.uniform(1.6, 2.2);
    std::array<double, 5> a{}, alpha{};  // radial harmonics k = 2..4
    std::array<double, 4> c{}, gamma{};  // lift harmonics k = 1..3
    for (std::size_t k = 2; k <= 4; ++k) {
      a[k] = random.uniform(-0.08, 0.08);
      alpha[k] = random.uniform(0, 2 * kPi);
    }
    for (std::size_t k = 1; k <= 3; ++k) {
      c[k] = random.uniform(-0.05, 0.05);
      gamma[k] = random.uniform(0, 2 * kPi);
    }
    // Position, first and second derivative of the core at theta.
    auto core = [&](double th) {
      double r = 1 + b * std::cos(th), r1 = -b * std::sin(th), r2 = -b * std::cos(th);
      double z = 0, z1 = 0, z2 = 0;
      for (std::size_t k = 2; k <= 4; ++k) {
        const double kk = static_cast<double>(k), arg = kk * th + alpha[k];
        r += a[k] * std::cos(arg);
        r1 -= kk * a[k] * std::sin(arg);
        r2 -= kk * kk * a[k] * std::cos(arg);
      }
      for (std::size_t k = 1; k <= 3; ++k) {
        const double kk = static_cast<double>(k), arg = kk * th + gamma[k];
        z += c[k] * std::sin(arg);
        z1 += kk * c[k] * std::cos(arg);
        z2 -= kk * kk * c[k] * std::sin(arg);
      }
      const double co = std::cos(th), si = std::sin(th);
      return std::array<Point3, 3>{
          Point3{r * co, r * si, z}, Point3{r1 * co - r * si, r1 * si + r * co, z1},
          Point3{r2 * co - 2 * r1 * si - r * co, r2 * si + 2 * r1 * co - r * si, z2}};
    };
    double curvature = 0;
    for (int i = 0; i < 4096; ++i) {
      const auto d = core(2 * kPi * i / 4096);
      const double speed = length(d[1]);
      curvature = std::max(curvature, length(cross(d[1], d[2])) / (speed * speed * speed));
    }
    const double tube = 0.6 / curvature;
    struct Bump {
      double amplitude, phase;
      int along, around;
    };
    std::array<Bump, 3> bumps{};
    for (Bump& bump : bumps) {
      bump.amplitude = random.uniform(0, 0.066);
      bump.phase = random.uniform(0, 2 * kPi);
      bump.along = 1 + static_cast<int>(random.next() % 4);
      bump.around = 1 + static_cast<int>(random.next() % 3);
    }
    const int rings_count = 4 * n, sides = n / 2;
    std::vector<Ring> rings;
    std::vector<double> thetas;
    for (int i = 0; i < rings_count; ++i) {
      const double th = 2 * kPi * (i + 0.31) / rings_count;
      const auto d = core(th);
      rings.push_back(ring_at(d[0], d[1], {0, 0, 1}, tube,
                              staggered_phase(static_cast<std::size_t>(i), sides)));
      thetas.push_back(th);
    }
    Surface out;
    append(out,
           closed_sweep(rings, sides,
                        [&](std::size_t ring, double phi) {
                          double f = 1;
                          for (const Bump& bump : bumps)
                            f += bump.amplitude * std::sin(bump.along * thetas[ring] +
                                                           bump.around * phi + bump.phase);
                          return f;
                        }),
           odd_motion(0));
    return out;
  });
}

}  // namespace imm::dim3
