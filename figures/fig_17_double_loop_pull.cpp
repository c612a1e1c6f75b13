// Paper Fig. 17 (right): "volumetric ARAP deformation exposing the topology" of the double-loop
// torus, and in its last column "the double-loop torus further deformed into a single-loop". The
// torus (a tube whose core winds twice around the z axis, its two strands 0.3 to 0.44 apart with
// a tube radius of 0.3: they overlap all the way round) is meshed with its helper box (§6.2; the
// box's tets are dropped) and pulled apart by ARAP: every fourth ring of the tube is a handle
// moved away from the other strand over the same angle (radially outwards only), by 0.75 times
// their offset (the strands end up 0.75 to 1.1 apart, more than the tube's diameter). Then
// further, from there, into a single loop: every other ring follows a path of core curves to a
// circle of the core's length (below, at "single loop"). The same handles on the naive glued
// mesh of the same background tets. The deformed input has ZERO self-intersecting triangle pairs
// on the unglued mesh after each (counted exactly, dim3::check_generic_surface), no inverted tet,
// and at the end its core winds once around z; the glued mesh keeps intersecting pairs after the
// pull and inverts tets on the way to the single loop (its overlapping strands share their
// tets). Pictures of both, side by side.
#include "deform/arap.h"
#include "deform/convert.h"
#include "dim3/generators3.h"
#include "core/rational.h"
#include "dim3/self_connecting.h"
#include "figures/deform_common.h"
#include "figures/figure_common.h"

#include <iomanip>
#include <map>
#include <numbers>

#include <Eigen/Geometry>

using namespace imm;

namespace {

/// A handle ring's rigid motion: its rest points x go to `to + (x - from) * rotation^T`.
struct RingPose {
  Eigen::RowVector3d from, to;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

struct Deformed {
  Eigen::MatrixXd positions;
  dim3::Surface surface;
  figures::Crossings crossing;
  std::size_t inverted = 0;
  int iterations = 0;        ///< ARAP iterations over all steps
  double energy = 0.0;       ///< ARAP energy at the end, over the rest volume
  double cpu_seconds = 0.0;  ///< process CPU of the precomputation and the steps
};

/// Volumetric ARAP whose handles are the carrying vertices of each ring's input vertices, moved
/// by the ring's pose (averaged where a mesh vertex carries several rings: on the glued mesh the
/// two strands' poses are averaged there), in warm-started steps from `start`: one pose per ring
/// per step.
Deformed follow(const deform::SimplexMesh<3>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
                const dim3::Surface& input, const std::vector<std::vector<std::size_t>>& rings,
                const std::vector<std::vector<RingPose>>& steps, const Eigen::MatrixXd& start) {
  const double cpu_start = process_cpu_seconds();
  std::map<Eigen::Index, std::vector<std::size_t>> carried;  // handle -> the rings it carries
  for (std::size_t r = 0; r < rings.size(); ++r)
    for (Eigen::Index v : figures::carrying_vertices(mesh, embedding, rings[r])) carried[v].push_back(r);
  std::vector<Eigen::Index> handles;
  for (const auto& [v, rs] : carried) handles.push_back(v);
  const deform::ArapData<3> data = deform::arap_precompute<3>(mesh, handles);
  if (!data.ok()) throw std::runtime_error("ARAP precomputation: " + data.error);
  Deformed d;
  d.positions = start;
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), 3);
  for (const std::vector<RingPose>& poses : steps) {
    Eigen::Index h = 0;
    for (const auto& [v, rs] : carried) {
      const Eigen::RowVector3d x = mesh.vertices.row(v);
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
      for (std::size_t r : rs) sum += poses[r].to + (x - poses[r].from) * poses[r].rotation.transpose();
      targets.row(h++) = sum / static_cast<double>(rs.size());
    }
    const deform::ArapReport report = deform::arap_solve<3>(data, targets, d.positions, {.max_iterations = 100});
    d.iterations += report.iterations;
    d.energy = report.energies.back() / data.volume;
  }
  d.cpu_seconds = process_cpu_seconds() - cpu_start;
  d.surface = figures::moved_surface(input, deform::embedded_positions(d.positions, mesh.elements, embedding));
  d.crossing = figures::crossings(d.surface);
  d.inverted = deform::inverted_elements<3>(d.positions, mesh.elements).size();
  return d;
}

/// Frames (columns: tangent, normal, binormal) along the closed polyline `p`, one per point:
/// `start` turned onto the first tangent, carried from point to point by the smallest rotation
/// between consecutive tangents, and the roll this leaves after one round (about the first
/// tangent) undone evenly along the curve. `roll`: the previous curve's roll on entry (the one
/// within pi of it is taken, so the frames change continuously along a path of curves), this
/// curve's on return.
std::vector<Eigen::Matrix3d> curve_frames(const std::vector<Eigen::RowVector3d>& p, const Eigen::Matrix3d& start,
                                          double& roll) {
  const std::size_t m = p.size();
  std::vector<Eigen::Vector3d> tangent(m);
  for (std::size_t i = 0; i < m; ++i) tangent[i] = (p[(i + 1) % m] - p[(i + m - 1) % m]).transpose().normalized();
  auto turn = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return Eigen::Quaterniond::FromTwoVectors(a, b).toRotationMatrix();
  };
  std::vector<Eigen::Matrix3d> frame(m);
  frame[0] = turn(start.col(0), tangent[0]) * start;
  for (std::size_t i = 1; i < m; ++i) frame[i] = turn(tangent[i - 1], tangent[i]) * frame[i - 1];
  const Eigen::Matrix3d round = turn(tangent[m - 1], tangent[0]) * frame[m - 1];
  double r = std::atan2(tangent[0].dot(frame[0].col(1).cross(round.col(1))), frame[0].col(1).dot(round.col(1)));
  r += 2 * std::numbers::pi * std::round((roll - r) / (2 * std::numbers::pi));
  roll = r;
  for (std::size_t i = 0; i < m; ++i)
    frame[i] = Eigen::AngleAxisd(-r * static_cast<double>(i) / static_cast<double>(m), tangent[i]).toRotationMatrix() * frame[i];
  return frame;
}

/// The poses of the handle rings `handle_rings` (ring ids) along a path of closed core curves
/// `path` (first: the cores where the rings are now, `rest_core` + the pull): each ring moved to
/// its core point on the curve and turned by its frame's rotation since the first curve. One pose
/// list per curve after the first.
std::vector<std::vector<RingPose>> poses_along(const std::vector<std::vector<Eigen::RowVector3d>>& path,
                                               const std::vector<Eigen::RowVector3d>& rest_core,
                                               const std::vector<std::size_t>& handle_rings) {
  Eigen::Matrix3d start;
  const Eigen::Vector3d t0 = (path[0][1] - path[0].back()).transpose().normalized();
  start.col(0) = t0;
  start.col(1) = Eigen::Vector3d::UnitZ().cross(t0).normalized();
  start.col(2) = t0.cross(start.col(1));
  double roll = 0;
  const std::vector<Eigen::Matrix3d> first = curve_frames(path[0], start, roll);
  std::vector<Eigen::Matrix3d> previous = first;
  std::vector<std::vector<RingPose>> steps;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const std::vector<Eigen::Matrix3d> frames = curve_frames(path[k], previous[0], roll);
    std::vector<RingPose> poses;
    for (std::size_t i : handle_rings) poses.push_back({rest_core[i], path[k][i], frames[i] * first[i].transpose()});
    steps.push_back(std::move(poses));
    previous = frames;
  }
  return steps;
}

/// Turns of the closed polyline `p` around the vertical line through `centre` (signed).
double turns_around(const std::vector<Eigen::RowVector3d>& p, const Eigen::RowVector3d& centre) {
  double angle = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::RowVector3d a = p[i] - centre, b = p[(i + 1) % p.size()] - centre;
    angle += std::atan2(a(0) * b(1) - a(1) * b(0), a(0) * b(0) + a(1) * b(1));
  }
  return angle / (2 * std::numbers::pi);
}

/// The twist of the handle rings' framing around a horizontal loop (signed turns, right-handed
/// about the loop's direction): the rings' rest up direction (z made normal to the rest core, the
/// generator's ring frame) turned by the final `poses`, its angle about the loop's tangent from
/// z (which is parallel along a horizontal loop) summed from ring to ring (each step within pi)
/// and back to the first.
double twist_turns(const std::vector<RingPose>& poses, const std::vector<Eigen::RowVector3d>& rest_tangent) {
  const std::size_t m = poses.size();
  std::vector<double> angle;
  for (std::size_t r = 0; r < m; ++r) {
    const Eigen::RowVector3d up = (Eigen::RowVector3d::UnitZ() - rest_tangent[r](2) * rest_tangent[r]).normalized() *
                                  poses[r].rotation.transpose();
    const Eigen::RowVector3d side = (poses[(r + 1) % m].to - poses[(r + m - 1) % m].to).cross(Eigen::RowVector3d::UnitZ());
    angle.push_back(std::atan2(up.dot(side.normalized()), up(2)));
  }
  double total = 0;
  for (std::size_t r = 0; r < m; ++r) {
    const double step = angle[(r + 1) % m] - angle[r];
    total += step - 2 * std::numbers::pi * std::round(step / (2 * std::numbers::pi));
  }
  return total / (2 * std::numbers::pi);
}

/// The writhe of the closed polyline `p`'s projection to the xy plane: the sum over the pairs of
/// its segments whose projections cross of +1 when (upper segment x lower segment) points up
/// (a right-handed crossing), else -1. Exact (rationals on the doubles); throws when the
/// projection is not generic (segments touching, collinear, or crossing at equal heights).
int xy_writhe(const std::vector<Eigen::RowVector3d>& p) {
  const std::size_t m = p.size();
  auto q = [&](std::size_t i, int a) { return Rational(p[i % m](a)); };
  auto sign = [](const Rational& x) { return sgn(x); };
  int writhe = 0;
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 2; j < m; ++j) {
      if ((j + 1) % m == i) continue;  // adjacent through the closing segment
      const Rational dpx = q(i + 1, 0) - q(i, 0), dpy = q(i + 1, 1) - q(i, 1);
      const Rational dqx = q(j + 1, 0) - q(j, 0), dqy = q(j + 1, 1) - q(j, 1);
      const Rational wx = q(j, 0) - q(i, 0), wy = q(j, 1) - q(i, 1);
      const Rational denominator = dpx * dqy - dpy * dqx;
      if (sign(denominator) == 0) {
        if (sign(wx * dpy - wy * dpx) == 0) throw std::runtime_error("xy_writhe: collinear segments in the projection");
        continue;  // parallel
      }
      const Rational lambda = (wx * dqy - wy * dqx) / denominator, mu = (wx * dpy - wy * dpx) / denominator;
      if (lambda < 0 || lambda > 1 || mu < 0 || mu > 1) continue;
      if (lambda == 0 || lambda == 1 || mu == 0 || mu == 1) throw std::runtime_error("xy_writhe: segments touch in the projection");
      const Rational height = q(i, 2) + lambda * (q(i + 1, 2) - q(i, 2)) - q(j, 2) - mu * (q(j + 1, 2) - q(j, 2));
      if (sign(height) == 0) throw std::runtime_error("xy_writhe: the curve meets itself");
      writhe += sign(height) * sign(denominator);
    }
  return writhe;
}

/// The centroid of each ring of a deformed tube (`sides` consecutive vertices per ring).
std::vector<Eigen::RowVector3d> ring_centroids(const dim3::Surface& tube, int sides) {
  std::vector<Eigen::RowVector3d> out(tube.vertices.size() / static_cast<std::size_t>(sides), Eigen::RowVector3d::Zero());
  for (std::size_t v = 0; v < tube.vertices.size(); ++v)
    out[v / static_cast<std::size_t>(sides)] += Eigen::RowVector3d(tube.vertices[v].data()) / sides;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_17_double_loop_pull");
    figures::describe("Fig. 17 (right)",
                      "the double-loop torus's tet mesh (helper cube discarded) deformed by volumetric ARAP, "
                      "exposing its topology: the two strands come apart, and further into a single loop; a glued mesh keeps "
                      "them stuck.");
    const int n = args.quick ? 24 : 32;
    const int sides = n / 2;
    const dim3::Surface torus = dim3::double_loop_torus(n);
    const std::size_t before = figures::crossings(torus).pairs;
    figures::expect(before > 0, "the two strands of the double-loop torus intersect");
    // The generator's layout: 2n rings of n/2 vertices, ring i at core angle t_i, ring i + n on
    // the other strand over the same angle. Checked: every vertex of a ring is at the tube's
    // radius 0.3 from the ring's centroid (the core point).
    figures::expect(torus.vertices.size() == static_cast<std::size_t>(2 * n * sides), "double_loop_torus: 2n rings of n/2 vertices");
    const std::vector<Eigen::RowVector3d> core = ring_centroids(torus, sides);
    double radius_error = 0;
    for (int i = 0; i < 2 * n; ++i)
      for (int k = 0; k < sides; ++k)
        radius_error = std::max(radius_error, std::abs((Eigen::RowVector3d(torus.vertices[static_cast<std::size_t>(i * sides + k)].data()) -
                                                        core[static_cast<std::size_t>(i)]).norm() - 0.3));
    figures::expect(radius_error < 1e-9, "every ring's vertices lie on the tube (radius 0.3) around the ring's centroid");
    auto ring = [&](int i) {
      std::vector<std::size_t> vertices;
      for (int k = 0; k < sides; ++k) vertices.push_back(static_cast<std::size_t>(i * sides + k));
      return vertices;
    };
    // Each strand moves away from the other by 0.75 times their offset (2.5 times as far apart:
    // 0.75 to 1.1, beyond the tube's diameter 0.6), the radial part outwards only: the outer
    // strand takes the inner one's share, so the inner strand is not squeezed towards the axis
    // (moved inwards, its inner side folded: 5 self-intersecting pairs and 11 inverted tets of
    // the unglued mesh at n = 32, resolution 28, measured). `pulled`: every ring's core moved so
    // (the handles of the pull are every fourth ring).
    constexpr double kPull = 0.75;
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (const auto& c : core) centre += c / static_cast<double>(core.size());
    std::vector<Eigen::RowVector3d> pulled;
    for (int i = 0; i < 2 * n; ++i) {
      const Eigen::RowVector3d away = core[static_cast<std::size_t>(i)] - core[static_cast<std::size_t>((i + n) % (2 * n))];
      Eigen::RowVector3d radial = core[static_cast<std::size_t>(i)] - centre;
      radial(2) = 0;
      radial.normalize();
      pulled.push_back(core[static_cast<std::size_t>(i)] + kPull * (away + std::abs(away.dot(radial)) * radial));
    }
    std::vector<std::vector<std::size_t>> rings;
    std::vector<std::vector<RingPose>> pull_steps(4);
    for (int i = 0; i < 2 * n; i += 4) {
      rings.push_back(ring(i));
      for (int step = 1; step <= 4; ++step)
        pull_steps[static_cast<std::size_t>(step - 1)].push_back(
            {core[static_cast<std::size_t>(i)],
             core[static_cast<std::size_t>(i)] + (pulled[static_cast<std::size_t>(i)] - core[static_cast<std::size_t>(i)]) * step / 4.0});
    }

    dim3::MeshOptions options;
    options.resolution = args.quick ? 20 : 28;
    const auto [im, mesh, in] = figures::immerse_and_mesh(torus, options, "the double-loop torus");
    figures::expect(!im.helper_boxes.empty(), "the double-loop torus is immersible with a helper box");

    const Deformed unglued = follow(in.unglued, in.unglued_embedding, torus, rings, pull_steps, in.unglued.vertices);
    const Deformed glued = follow(in.glued.mesh, in.glued_embedding, torus, rings, pull_steps, in.glued.mesh.vertices);
    std::cout << "deformed input, self-intersecting triangle pairs (exact): unglued " << unglued.crossing.pairs << ", glued "
              << glued.crossing.pairs << " (input " << before << "); inverted tets: unglued " << unglued.inverted
              << ", glued " << glued.inverted << '\n';
    figures::expect(unglued.crossing.pairs == 0, "Fig. 17: pulled apart on the unglued mesh, the strands no longer intersect (0 pairs)");
    figures::expect(unglued.inverted == 0, "no inverted tet in the deformed unglued mesh");
    figures::expect(glued.crossing.pairs > 0, "the glued baseline keeps the strands stuck: " + std::to_string(glued.crossing.pairs) +
                                                  " self-intersecting pairs after the same pull");

    // Fig. 17, last column: further into a single loop. The core goes from where the pull left
    // it to a circle of the same length (radius L / 2 pi: the tube is not stretched), core angle
    // t -> t / 2 (the outer strand's middle stays on the +x side, the inner strand swings over
    // to the -x side), along the straight path between the two lifted in z by 4 s (1 - s) kLift
    // sin(t / 2): the two strands' heights get further apart the way they already differ, so the
    // core's crossing in the xy projection shrinks into a cusp and disappears above the other
    // strand (a Reidemeister I move) without the core meeting itself (sampled every 0.02 in s,
    // core points over 1.2 apart along it stay over 0.74 apart, more than the tube's diameter;
    // lifted the other way it passes through itself, which the twist check below sees). The
    // handles (every other ring) follow the path's core points and its rotation-minimizing
    // frames in warm-started steps; only the end is checked (ARAP has no contact).
    constexpr double kLift = 0.8;
    const int loop_steps = args.quick ? 8 : 16;
    double length = 0;
    for (int i = 0; i < 2 * n; ++i) length += (core[static_cast<std::size_t>((i + 1) % (2 * n))] - core[static_cast<std::size_t>(i)]).norm();
    const double circle_radius = length / (2 * std::numbers::pi);
    std::vector<std::vector<Eigen::RowVector3d>> path;
    for (int k = 0; k <= loop_steps; ++k) {
      const double s = static_cast<double>(k) / loop_steps;
      std::vector<Eigen::RowVector3d> curve;
      for (int i = 0; i < 2 * n; ++i) {
        const double half = std::numbers::pi * (i + 0.25) / n;  // the generator's t / 2
        const Eigen::RowVector3d circle = centre + circle_radius * Eigen::RowVector3d(std::cos(half), std::sin(half), 0);
        curve.push_back((1 - s) * pulled[static_cast<std::size_t>(i)] + s * circle +
                        4 * s * (1 - s) * kLift * std::sin(half) * Eigen::RowVector3d::UnitZ());
      }
      path.push_back(std::move(curve));
    }
    std::vector<std::size_t> loop_ring_ids;
    std::vector<std::vector<std::size_t>> loop_rings;
    for (int i = 0; i < 2 * n; i += 2) {
      loop_ring_ids.push_back(static_cast<std::size_t>(i));
      loop_rings.push_back(ring(i));
    }
    const std::vector<std::vector<RingPose>> loop_poses = poses_along(path, core, loop_ring_ids);
    const Deformed unglued_loop = follow(in.unglued, in.unglued_embedding, torus, loop_rings, loop_poses, unglued.positions);
    const Deformed glued_loop = follow(in.glued.mesh, in.glued_embedding, torus, loop_rings, loop_poses, glued.positions);
    std::vector<Eigen::RowVector3d> rest_tangent;
    for (std::size_t i : loop_ring_ids)
      rest_tangent.push_back((core[(i + 1) % core.size()] - core[(i + core.size() - 1) % core.size()]).normalized());
    const double twist = twist_turns(loop_poses.back(), rest_tangent);
    const int input_writhe = xy_writhe(core);
    const double input_turns = turns_around(core, centre);
    const double loop_turns = turns_around(ring_centroids(unglued_loop.surface, sides), centre);
    const double glued_turns = turns_around(ring_centroids(glued_loop.surface, sides), centre);
    auto row = [](const std::string& what, const Deformed& d, double turns) {
      std::ostringstream out;
      out << "| " << what << " | " << d.crossing.pairs << " | " << d.inverted << " | " << std::fixed << std::setprecision(2) << turns
          << " | " << std::scientific << std::setprecision(2) << d.energy << " | " << d.iterations << " | " << std::fixed
          << std::setprecision(2) << d.cpu_seconds << " |\n";
      return out.str();
    };
    std::cout << "single loop: unglued " << unglued_loop.crossing.pairs << " pairs, " << unglued_loop.inverted << " inverted, core turns "
              << loop_turns << "; glued " << glued_loop.crossing.pairs << " pairs, " << glued_loop.inverted << " inverted, core turns "
              << glued_turns << '\n';
    figures::expect(std::lround(input_turns) == 2, "the input's core winds twice around the z axis");
    figures::expect(std::lround(loop_turns) == 1,
                    "Fig. 17 (last column): the unglued mesh deformed further: its core (ring centroids) winds once around the z axis");
    // The rings' frames are carried continuously along the path (the roll closing each curve's
    // frames is taken within pi of the previous curve's), so the linking number of the core with the rings' up
    // direction is kept. On the input it is the writhe of the core's xy projection (the up
    // direction is z there: the blackboard framing), on the horizontal circle the rings' twist
    // (Calugareanu: linking = twist + writhe, and a plane curve has no writhe). Paths whose
    // frames jump (one step straight to the circle; the same path unlifted) or whose core passes
    // through itself (lifted the other way) end with another twist (measured: 0, 0 and the
    // opposite sign): states no continuous deformation reaches.
    figures::expect(input_writhe != 0 && std::lround(twist) == input_writhe,
                    "the handle rings end twisted by " + std::to_string(std::lround(twist)) +
                        " turn(s) around the single loop, the writhe of the input core's xy projection (" +
                        std::to_string(input_writhe) + "): the linking number kept");
    figures::expect(unglued_loop.crossing.pairs == 0,
                    "Fig. 17 (last column): the deformed single loop has 0 self-intersecting triangle pairs (exact)");
    figures::expect(unglued_loop.inverted == 0, "no inverted tet in the single loop");
    // The glued mesh's handles on the two strands share vertices where the strands overlap (their
    // targets averaged there): it cannot follow without inverting tets.
    figures::expect(glued_loop.inverted > 0, "the glued baseline cannot follow the same path: " +
                                                 std::to_string(glued_loop.inverted) + " inverted tets, " +
                                                 std::to_string(glued_loop.crossing.pairs) + " self-intersecting pairs");

    figures::write(args, "fig17_unglued_pulled.obj", dim3::format_obj(unglued.surface));
    figures::write(args, "fig17_glued_pulled.obj", dim3::format_obj(glued.surface));
    figures::write(args, "fig17_unglued_loop.obj", dim3::format_obj(unglued_loop.surface));
    figures::write(args, "fig17_glued_loop.obj", dim3::format_obj(glued_loop.surface));
    const render::View view{30, 30, 2};
    figures::deformed_outputs(args, "fig17_unglued_pulled", "unglued, strands pulled apart", unglued.surface,
                               unglued.crossing, in.unglued, unglued.positions, mesh.mesh.reference, view);
    figures::deformed_outputs(args, "fig17_glued_pulled", "glued baseline, same pull", glued.surface, glued.crossing,
                               in.glued.mesh, glued.positions, {}, view);
    figures::deformed_outputs(args, "fig17_unglued_loop", "unglued, further into a single loop", unglued_loop.surface,
                               unglued_loop.crossing, in.unglued, unglued_loop.positions, mesh.mesh.reference, view);
    figures::deformed_outputs(args, "fig17_glued_loop", "glued baseline, same path", glued_loop.surface, glued_loop.crossing,
                               in.glued.mesh, glued_loop.positions, {}, view);
    std::ostringstream md;
    md << "# Fig. 17: the double-loop torus pulled apart, then into a single loop\n\n"
       << "- input: double_loop_torus(" << n << "), " << torus.triangle_count() << " triangles, " << before
       << " self-intersecting triangle pairs; " << im.helper_boxes.size() << " helper box(es)\n"
       << "- unglued mesh: " << in.unglued.element_count() << " tets; glued: " << in.glued.mesh.element_count() << " tets\n"
       << "- pull: " << rings.size() << " handle rings, each moved away from the other strand (radially outwards only) by 0.75 "
       << "times their offset, in 4 steps\n"
       << "- single loop: " << loop_rings.size() << " handle rings moved along a path of core curves to a circle of radius "
       << std::setprecision(3) << circle_radius << " (the core's length) in " << loop_steps
       << " warm-started steps, frames rotation-minimizing (" << std::lround(twist) << " turn of twist around the loop)\n\n"
       << "| mesh, stage | self-intersecting pairs after | inverted tets | core turns around z | ARAP energy / volume | ARAP "
          "iterations | CPU s |\n| --- | --- | --- | --- | --- | --- | --- |\n"
       << row("unglued, pulled", unglued, turns_around(ring_centroids(unglued.surface, sides), centre))
       << row("glued, pulled", glued, turns_around(ring_centroids(glued.surface, sides), centre))
       << row("unglued, single loop", unglued_loop, loop_turns) << row("glued, single loop", glued_loop, glued_turns);
    figures::write(args, "fig17.md", md.str());
    std::cout << md.str();
  });
}
