#include "dim3/sweeps.h"

namespace imm::dim3::sweep {

Motion rotation(const Point3& axis, double angle, const Point3& shift) {
  const Point3 k = normalized(axis);
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  Motion m;
  m.rows = {Point3{c + t * k[0] * k[0], t * k[0] * k[1] - s * k[2], t * k[0] * k[2] + s * k[1]},
            Point3{t * k[1] * k[0] + s * k[2], c + t * k[1] * k[1], t * k[1] * k[2] - s * k[0]},
            Point3{t * k[2] * k[0] - s * k[1], t * k[2] * k[1] + s * k[0], c + t * k[2] * k[2]}};
  m.shift = shift;
  return m;
}

Motion odd_motion(int k, const Point3& about) {
  const double a = 0.0123 + 0.0031 * k;
  Motion m = rotation({1.0 + 0.31 * k, std::numbers::sqrt2, std::numbers::phi + 0.17 * k}, a);
  const Point3 turned = m.apply(about);
  m.shift =
      plus(minus(about, turned), Point3{0.00137 * (k + 1), -0.00211 * (k + 1), 0.00173 * (k + 1)});
  return m;
}

void append(Surface& out, const Surface& part, const Motion& motion) {
  const auto base = static_cast<std::uint32_t>(out.vertices.size());
  for (const Point3& p : part.vertices) out.vertices.push_back(motion.apply(p));
  for (const Triangle& t : part.triangles) {
    out.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    out.source_face.push_back(static_cast<std::uint32_t>(out.source_face.size()));
  }
}

double staggered_phase(std::size_t index, int sides) {
  const double jitter =
      0.1 * std::fmod(0.6180339887498949 * static_cast<double>(index) + 0.137, 1.0);
  return 2 * kPi / sides * (0.5 * static_cast<double>(index & 1U) + jitter);
}

Ring ring_at(const Point3& centre, const Point3& tangent, const Point3& reference, double radius,
             double phase) {
  const Point3 t = normalized(tangent);
  const Point3 u = normalized(minus(reference, times(dot(reference, t), t)));
  return {centre, u, cross(t, u), radius, phase};
}

Ring revolution_ring(double rho, double z, double phase) {
  return {{0, 0, z}, {1, 0, 0}, {0, 1, 0}, rho, phase};
}

Point3 ring_point(const Ring& ring, int j, int sides, double scale) {
  const double phi = ring.phase + 2 * kPi * j / sides;
  const double r = ring.radius * scale;
  return plus(ring.centre,
              plus(times(r * std::cos(phi), ring.u), times(r * std::sin(phi), ring.v)));
}

Surface sweep_bands(const std::vector<Ring>& rings, int sides, bool closed,
                    const RadiusScale& scale) {
  Surface s;
  s.vertices.reserve(rings.size() * static_cast<std::size_t>(sides) + 2);
  for (std::size_t i = 0; i < rings.size(); ++i) {
    for (int j = 0; j < sides; ++j) {
      const double phi = rings[i].phase + 2 * kPi * j / sides;
      s.vertices.push_back(ring_point(rings[i], j, sides, scale ? scale(i, phi) : 1.0));
    }
  }
  auto id = [&](std::size_t i, int j) {
    return static_cast<std::uint32_t>((i % rings.size()) * static_cast<std::size_t>(sides) +
                                      static_cast<std::size_t>(j % sides));
  };
  const std::size_t bands = closed ? rings.size() : rings.size() - 1;
  for (std::size_t i = 0; i < bands; ++i) {
    for (int j = 0; j < sides; ++j) {
      const std::uint32_t a = id(i, j), b = id(i, j + 1), c = id(i + 1, j + 1), d = id(i + 1, j);
      // The shorter diagonal: staggered rings are offset by half a step, alternately forwards
      // and backwards, and the long diagonal would fold coarse tubes.
      if (length(minus(s.vertices[a], s.vertices[c])) <=
          length(minus(s.vertices[b], s.vertices[d]))) {
        s.triangles.push_back({a, b, c});
        s.triangles.push_back({a, c, d});
      } else {
        s.triangles.push_back({a, b, d});
        s.triangles.push_back({b, c, d});
      }
    }
  }
  return s;
}

Surface closed_sweep(const std::vector<Ring>& rings, int sides, const RadiusScale& scale) {
  Surface s = sweep_bands(rings, sides, true, scale);
  s.source_face.resize(s.triangles.size());
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    s.source_face[t] = static_cast<std::uint32_t>(t);
  return s;
}

Surface capped_sweep(const std::vector<Ring>& rings, int sides, const Point3& start_pole,
                     const Point3& end_pole) {
  Surface s = sweep_bands(rings, sides, false, {});
  const auto first = static_cast<std::uint32_t>(s.vertices.size());
  s.vertices.push_back(start_pole);
  s.vertices.push_back(end_pole);
  const auto last_ring =
      static_cast<std::uint32_t>((rings.size() - 1) * static_cast<std::size_t>(sides));
  for (int j = 0; j < sides; ++j) {
    const auto j0 = static_cast<std::uint32_t>(j), j1 = static_cast<std::uint32_t>((j + 1) % sides);
    s.triangles.push_back({first, j1, j0});
    s.triangles.push_back({last_ring + j0, last_ring + j1, first + 1});
  }
  s.source_face.resize(s.triangles.size());
  for (std::size_t t = 0; t < s.triangles.size(); ++t)
    s.source_face[t] = static_cast<std::uint32_t>(t);
  return s;
}

Ring cap_ring(const Ring& end, const Point3& outward, int k, double phase) {
  const double psi = k * (kPi / 2) / (kCapRings + 1);
  Ring r = end;
  r.centre = plus(end.centre, times(end.radius * std::sin(psi), outward));
  r.radius = end.radius * std::cos(psi);
  r.phase = phase;
  return r;
}

Surface round_capped_tube(const std::vector<Ring>& body, int sides) {
  std::vector<Ring> rings;
  const Ring& head = body.front();
  const Ring& tail = body.back();
  const Point3 back = times(-1.0, ring_tangent(head)), forward = ring_tangent(tail);
  std::size_t index = 0;
  for (int k = kCapRings; k >= 1; --k)
    rings.push_back(cap_ring(head, back, k, head.phase + staggered_phase(index++, sides)));
  for (Ring r : body) {
    r.phase += staggered_phase(index++, sides);
    rings.push_back(r);
  }
  for (int k = 1; k <= kCapRings; ++k)
    rings.push_back(cap_ring(tail, forward, k, tail.phase + staggered_phase(index++, sides)));
  return capped_sweep(rings, sides, plus(head.centre, times(head.radius, back)),
                      plus(tail.centre, times(tail.radius, forward)));
}

Surface cylinder(const Point3& a, const Point3& b, double radius, int sides, int body_rings,
                 const Point3& reference) {
  std::vector<Ring> body;
  const Point3 axis = minus(b, a);
  for (int i = 0; i < body_rings; ++i) {
    const double f = static_cast<double>(i) / (body_rings - 1);
    body.push_back(ring_at(plus(a, times(f, axis)), axis, reference, radius, 0.0));
  }
  return round_capped_tube(body, sides);
}

Surface unit_sphere(int n) {
  std::vector<Ring> rings;
  const int sides = 2 * n;
  for (int k = 1; k < n; ++k) {
    const double theta = kPi * k / n;
    rings.push_back(revolution_ring(std::sin(theta), -std::cos(theta),
                                    staggered_phase(static_cast<std::size_t>(k), sides)));
  }
  return capped_sweep(rings, sides, {0, 0, -1}, {0, 0, 1});
}

Surface revolve_closed(const std::function<std::array<double, 2>(double)>& profile, int samples,
                       int sides) {
  std::vector<Ring> rings;
  for (int i = 0; i < samples; ++i) {
    const auto [rho, z] = profile((i + 0.3183098861837907) / samples);
    rings.push_back(revolution_ring(rho, z, staggered_phase(static_cast<std::size_t>(i), sides)));
  }
  return closed_sweep(rings, sides);
}

Surface moved(const Surface& part, const Motion& motion) {
  Surface out;
  append(out, part, motion);
  return out;
}

Surface ring_torus(double major, double minor, int samples, int sides) {
  return revolve_closed(
      [major, minor](double s) {
        const double a = 2 * kPi * s;
        return std::array<double, 2>{major + minor * std::cos(a), minor * std::sin(a)};
      },
      samples, sides);
}

}  // namespace imm::dim3::sweep
