// Paper Fig. 22 (and §8): "we simulate the output mesh using FEM"; "our algorithm generated a
// quality tetrahedral mesh that is capable of separating all of the collided cylinders".
// Full mode with ../shared/data present: the paper's own quintuple torus (quintupleTorus.obj, a
// genus-5 plate, y in [-0.5, 0.5], with 24 arms hanging below it down to y = -3.5, one surface)
// meshed unglued on its Vega background (tet/quintupleTorus.veg, 84,938 tets), and the glued
// baseline of the same tets. The arms (the connected parts of the triangles below the plate)
// are hooks: straight down from the plate, then bent in towards the centre, where they collide
// with each other (97 pairs of arms, none with the plate). Hanging them under gravity does not
// separate them (at E = 1e4 they sag ~0.05), so the load pulls them straight: the plate held,
// each arm's end (its vertices within 0.3 of its farthest from where it leaves the plate) moved
// rigidly to hang straight below that root, its axis turned down, 1.1 x the arm's length along
// its surface below it, eased over 10 implicit Euler steps and held 4 more, under gravity. On
// the unglued mesh every arm is its own solid and straightens: ZERO self-intersecting triangle
// pairs after (counted exactly), no tet inverted at any step; on the glued baseline the arms are
// one lump at the centre, torn apart by the same load: pairs remain and thousands of tets invert.
// --quick, or ../shared absent: the generated quintuple torus (dim3::quintuple_torus: five
// overlapping tori in a ring and seven colliding capped cylinders through them and through each
// other, winding number 7 at the centre) meshed unglued, and the naive glued mesh of the same
// background tets. On both, a dynamic FEM simulation (deform::fem_step: implicit Euler,
// co-rotational material, gravity, a ground plane below) holds the ring of tori and lets
// everything else go. On the unglued mesh every cylinder is its own solid: all seven drop out of
// the tori (and out of each other's way down) onto the ground, and the deformed input has ZERO
// triangle pairs between a cylinder and a torus (counted exactly, dim3::check_generic_surface),
// no tet inverting at any step; on the glued mesh the cylinders are glued into the tori and hang
// there: pairs remain.
// Pictures: the input (collided faces red), the deformed inputs and deformed meshes.
#include "deform/convert.h"
#include "dim3/generators3.h"
#include "dim3/self_connecting.h"
#include "figures/deform_common.h"
#include "figures/figure_common.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <queue>
#include <set>

using namespace imm;

namespace {

std::string row(const std::string& name, const figures::Dropped& d) {
  std::ostringstream o;
  o << "| " << name << " | " << d.held << " | " << d.crossing.pairs << " | " << d.held_free_pairs << " | " << d.free_drop
    << " | " << d.inverted << " | " << d.most_inverted << " | " << d.newton_iterations << " (" << d.unconverged << ") |\n";
  return o.str();
}

/// Median and max of a run's per-step CPU seconds, as "0.41 / 0.97".
std::string step_times(const figures::Dropped& d) {
  std::vector<double> t = d.step_seconds;
  std::sort(t.begin(), t.end());
  std::ostringstream o;
  o.precision(3);
  o << t[t.size() / 2] << " / " << t.back();
  return o.str();
}

const char* kTableHead =
    "| mesh | held vertices | self-intersecting pairs after | pairs between held and free parts | mean drop of the "
    "free parts | inverted tets after | most inverted at a step | Newton iterations (steps not converged) |\n"
    "| --- | --- | --- | --- | --- | --- | --- | --- |\n";

/// One arm of quintupleTorus.obj: a connected part of the triangles below the plate.
struct Arm {
  std::vector<std::size_t> vertices;
  Eigen::Vector3d root;          ///< where it leaves the plate: its vertices' centroid in the band kBand below it, at y = kPlate
  std::size_t farthest = 0;      ///< its vertex farthest from the root
  std::vector<std::size_t> tip;  ///< its free end: the vertices within kTipDepth of the farthest distance from the root
  Eigen::Vector3d end_centre;    ///< the tip's centroid
  Eigen::AngleAxisd turn;        ///< turns the end's axis (from the centroid of the vertices 0.7-1.0 closer to the root to end_centre) to -y
  double length = 0.0;           ///< from the plate to `farthest` along its edges (kBand + the shortest path from the band)
};

const double kPlate = -0.5;    // the genus-5 plate spans y in [-0.5, 0.5]; the arms hang below
const double kBand = 0.1;      // the arm's vertices within kBand below the plate locate its root
const double kTipDepth = 0.3;  // the free end: about one arm diameter (radii 0.25 and 0.4)

Eigen::Vector3d point(const dim3::Surface& s, std::size_t v) {
  return {s.vertices[v][0], s.vertices[v][1], s.vertices[v][2]};
}

/// The shortest path along `edges` (per vertex its neighbours) from `from` to `to`.
double shortest_path(const dim3::Surface& s, const std::vector<std::vector<std::size_t>>& edges,
                     const std::vector<std::size_t>& from, std::size_t to) {
  std::vector<bool> done(s.vertices.size(), false);
  std::priority_queue<std::pair<double, std::size_t>, std::vector<std::pair<double, std::size_t>>, std::greater<>> queue;
  for (std::size_t v : from) queue.push({0.0, v});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (done[v]) continue;
    done[v] = true;
    if (v == to) return d;
    for (std::size_t w : edges[v])
      if (!done[w]) queue.push({d + (point(s, w) - point(s, v)).norm(), w});
  }
  throw std::runtime_error("figure check failed: an arm's end is not connected to its root");
}

/// The centroid of `vertices` of `s` (an arm's band, end or the vertices before its end).
Eigen::Vector3d centroid(const dim3::Surface& s, const std::vector<std::size_t>& vertices) {
  if (vertices.empty()) throw std::runtime_error("figure check failed: an arm too short to have a root, an end and an axis");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t v : vertices) sum += point(s, v);
  return sum / static_cast<double>(vertices.size());
}

/// The arms: the connected parts of the triangles with all three corners below the plate.
std::vector<Arm> arms_of(const dim3::Surface& input) {
  dim3::Surface below = input;
  below.triangles.clear();
  std::vector<std::vector<std::size_t>> edges(input.vertices.size());
  for (const auto& t : input.triangles)
    if (input.vertices[t[0]][1] < kPlate && input.vertices[t[1]][1] < kPlate && input.vertices[t[2]][1] < kPlate) {
      below.triangles.push_back(t);
      for (std::size_t k = 0; k < 3; ++k) {
        edges[t[k]].push_back(t[(k + 1) % 3]);
        edges[t[(k + 1) % 3]].push_back(t[k]);
      }
    }
  int parts = 0;
  const std::vector<int> part = figures::surface_parts(below, parts);
  std::map<int, Arm> by_part;
  for (std::size_t v = 0; v < input.vertices.size(); ++v)
    if (input.vertices[v][1] < kPlate) by_part[part[v]].vertices.push_back(v);
  std::vector<Arm> arms;
  for (auto& [p, arm] : by_part) {
    std::vector<std::size_t> band;
    for (std::size_t v : arm.vertices)
      if (input.vertices[v][1] >= kPlate - kBand) band.push_back(v);
    if (band.empty()) continue;  // not hanging from the plate (none in this file: checked by the count)
    arm.root = centroid(input, band);
    arm.root.y() = kPlate;
    auto from_root = [&](std::size_t v) { return (point(input, v) - arm.root).norm(); };
    arm.farthest = *std::max_element(arm.vertices.begin(), arm.vertices.end(),
                                     [&](std::size_t a, std::size_t b) { return from_root(a) < from_root(b); });
    const double reach = from_root(arm.farthest);
    std::vector<std::size_t> before;
    for (std::size_t v : arm.vertices) {
      if (from_root(v) >= reach - kTipDepth) arm.tip.push_back(v);
      if (from_root(v) >= reach - 1.0 && from_root(v) <= reach - 0.7) before.push_back(v);
    }
    arm.end_centre = centroid(input, arm.tip);
    arm.turn = Eigen::AngleAxisd(
        Eigen::Quaterniond::FromTwoVectors(arm.end_centre - centroid(input, before), Eigen::Vector3d(0, -1, 0)));
    arm.length = kBand + shortest_path(input, edges, band, arm.farthest);
    arms.push_back(std::move(arm));
  }
  return arms;
}

/// Per input vertex its arm (-1: the plate).
std::vector<int> arm_of_vertex(const dim3::Surface& input, const std::vector<Arm>& arms) {
  std::vector<int> arm(input.vertices.size(), -1);
  for (std::size_t a = 0; a < arms.size(); ++a)
    for (std::size_t v : arms[a].vertices) arm[v] = static_cast<int>(a);
  return arm;
}

/// Which parts of `surface` intersect (counted exactly): per triangle pair its two parts (`arm`
/// of its first vertex, -1 the plate).
struct Collisions {
  std::size_t plate_pairs = 0;                ///< triangle pairs between the plate and an arm
  std::set<std::pair<int, int>> arm_pairs;    ///< pairs of arms (a < b) with a triangle pair
};
Collisions collisions(const dim3::Surface& surface, const std::vector<int>& arm) {
  const dim3::SurfaceGenericity g = dim3::check_generic_surface(surface, /*keep_pairs=*/true);
  Collisions c;
  for (const auto& [i, j] : g.pairs) {
    const int a = arm[surface.triangles[i][0]], b = arm[surface.triangles[j][0]];
    if (a < 0 || b < 0) ++c.plate_pairs;
    else c.arm_pairs.insert({std::min(a, b), std::max(a, b)});
  }
  return c;
}

const double kStretch = 1.1;  // each arm's end goes 1.1 x the arm's length along its surface below its root

/// The load on one mesh: the carrying vertices of the plate held; those of each arm's tip moved
/// rigidly, along the eased fraction of the motion, from rest to hanging straight below the arm's
/// root: its centroid kStretch x the arm's length below the root, turned by `turn` (its axis
/// down). A mesh vertex carrying the tips of several arms, which happens only where they are
/// glued (counted in `shared_tip_vertices`), goes to the mean of their targets. `pull_steps`
/// steps, then held there for the rest of `steps`.
figures::Dropped pull_straight(const deform::SimplexMesh<3>& mesh, const std::vector<deform::EmbeddedPoint>& embedding,
                               const dim3::Surface& input, const std::vector<std::size_t>& plate,
                               const std::vector<Arm>& arms, const std::vector<bool>& held_part,
                               const deform::FemOptions& fem, int pull_steps, int steps, std::size_t& shared_tip_vertices) {
  std::map<Eigen::Index, std::vector<int>> drivers;  // mesh vertex -> the arms whose tip it carries (none: the plate)
  for (Eigen::Index v : figures::carrying_vertices(mesh, embedding, plate)) drivers[v];
  for (std::size_t a = 0; a < arms.size(); ++a)
    for (Eigen::Index v : figures::carrying_vertices(mesh, embedding, arms[a].tip)) {
      const auto [it, inserted] = drivers.try_emplace(v);
      figures::expect(inserted || !it->second.empty(), "no mesh vertex carries both the plate and an arm's tip");
      it->second.push_back(static_cast<int>(a));
    }
  shared_tip_vertices = 0;
  std::vector<Eigen::Index> handles;
  for (const auto& [v, d] : drivers) {
    handles.push_back(v);
    if (d.size() > 1) ++shared_tip_vertices;
  }
  auto targets = [&](int step) {
    const double t = std::min(1.0, static_cast<double>(step) / pull_steps);
    const double ease = 0.5 - 0.5 * std::cos(std::numbers::pi * t);  // starts and stops at rest
    Eigen::MatrixXd out(static_cast<Eigen::Index>(handles.size()), 3);
    for (std::size_t k = 0; k < handles.size(); ++k) {
      const Eigen::Vector3d rest = mesh.vertices.row(handles[k]).transpose();
      const std::vector<int>& d = drivers.at(handles[k]);
      Eigen::Vector3d target = d.empty() ? rest : Eigen::Vector3d::Zero();
      for (int a : d) {
        const Arm& arm = arms[static_cast<std::size_t>(a)];
        const Eigen::Vector3d hanging = arm.root - kStretch * arm.length * Eigen::Vector3d::UnitY();
        target += arm.end_centre + ease * (hanging - arm.end_centre) +
                  Eigen::AngleAxisd(ease * arm.turn.angle(), arm.turn.axis()) * (rest - arm.end_centre);
      }
      if (d.size() > 1) target /= static_cast<double>(d.size());
      out.row(static_cast<Eigen::Index>(k)) = target.transpose();
    }
    return out;
  };
  return figures::simulate(mesh, embedding, input, handles, targets, held_part, fem, steps);
}

/// Full mode on the paper's own quintuple torus on its Vega tets (the header's setup).
void run_real(const figures::FigureArgs& args, const std::string& obj, const std::string& veg) {
  const dim3::SurfaceReadResult read = dim3::read_surface(obj);
  figures::expect(read.report.ok(), "quintupleTorus.obj reads" + (read.report.ok() ? "" : ": " + read.report.summary()));
  const dim3::Surface& input = read.surface;
  const figures::Crossings before = figures::crossings(input);
  figures::expect(before.pairs > 0, "Fig. 22: the arms of the paper's quintuple torus collide");

  const std::vector<Arm> arms = arms_of(input);
  figures::expect(arms.size() == 24, "quintupleTorus.obj: 24 arms (the paper's \"cylinders\") hang below the plate");
  const std::vector<int> arm = arm_of_vertex(input, arms);
  std::vector<std::size_t> plate;
  std::vector<bool> held_part(input.vertices.size(), false);
  for (std::size_t v = 0; v < input.vertices.size(); ++v)
    if (arm[v] < 0) {
      plate.push_back(v);
      held_part[v] = true;
    }
  const Collisions collided = collisions(input, arm);
  figures::expect(collided.plate_pairs == 0 && !collided.arm_pairs.empty(),
                  "quintupleTorus.obj: the arms collide with each other (" + std::to_string(collided.arm_pairs.size()) +
                      " pairs of arms), not with the plate");

  dim3::MeshOptions options;
  options.background_path = veg;
  const auto [im, mesh, in] = figures::immerse_and_mesh(input, options, "quintupleTorus.obj");

  deform::FemOptions fem;  // E = 1e4, nu = 0.3, density 1
  fem.time_step = 1.0 / 30;
  fem.gravity = Eigen::Vector3d(0, -9.81, 0);
  fem.step_tolerance = 1e-4;
  // The unglued mesh converges in 3-5 Newton iterations a step. The glued one, torn by the same
  // load, does not converge in 10 in most steps; with the default 50 it took 583 iterations
  // (9 of the 14 steps still not converged), 14.8 s CPU a step, and ended with the same 662 pairs
  // and 5,047 inverted tets against 5,042 with 10 (BENCHMARKS.md, "Reused factorization").
  fem.max_newton_iterations = 10;
  const int pull_steps = 10, steps = 14;  // 1/3 s eased, then 2/15 s held
  std::size_t shared_unglued = 0, shared_glued = 0;
  const figures::Dropped unglued =
      pull_straight(in.unglued, in.unglued_embedding, input, plate, arms, held_part, fem, pull_steps, steps, shared_unglued);
  const figures::Dropped glued =
      pull_straight(in.glued.mesh, in.glued_embedding, input, plate, arms, held_part, fem, pull_steps, steps, shared_glued);
  const Collisions left_unglued = collisions(unglued.surface, arm);
  const Collisions left_glued = collisions(glued.surface, arm);

  std::ostringstream md;
  md << "# Fig. 22: the paper's quintuple torus under FEM\n\n"
     << "- input: quintupleTorus.obj (../shared/data), " << input.triangle_count() << " triangles, " << before.pairs
     << " self-intersecting triangle pairs: " << arms.size() << " arms hanging below the genus-5 plate (y >= -0.5), "
     << collided.arm_pairs.size() << " pairs of arms collide, " << collided.plate_pairs << " pairs with the plate\n"
     << "- unglued mesh on quintupleTorus.veg: " << in.unglued.element_count() << " tets, " << in.unglued.vertex_count()
     << " vertices; glued baseline: " << in.glued.mesh.element_count() << " tets, " << in.glued.mesh.vertex_count()
     << " vertices\n"
     << "- the load: the plate held; each arm's end (its input vertices within " << kTipDepth
     << " of its farthest from the root) moved rigidly, eased over " << pull_steps
     << " steps, to hang straight below the arm's root (its axis turned down, its centroid " << kStretch
     << " x the arm's length along its surface below the root), then held " << steps - pull_steps
     << " steps; gravity 9.81 along -y. Mesh vertices carrying the ends of several arms (glued only: "
     << shared_glued << "; unglued: " << shared_unglued << ") go to the mean of their targets\n"
     << "- dynamic FEM (implicit Euler, h = " << fem.time_step << " s, " << steps
     << " steps, co-rotational E = 1e4, nu = 0.3, density 1, at most " << fem.max_newton_iterations
     << " Newton iterations a step), one FemSolver per mesh\n"
     << "- CPU seconds per step (median / max, the process: all threads): unglued " << step_times(unglued) << ", glued "
     << step_times(glued) << "\n\n"
     << kTableHead << row("unglued", unglued) << row("glued", glued)
     << "\n(\"pairs between held and free parts\": plate-arm pairs; \"mean drop\": of the arms' input vertices, along -y.)\n\n"
     << "Pairs of arms still colliding: unglued " << left_unglued.arm_pairs.size() << ", glued "
     << left_glued.arm_pairs.size() << " of the input's " << collided.arm_pairs.size() << ".\n\n"
     << "| arm | root (x, z) | length | end turned (degrees) | end vertices |\n| --- | --- | --- | --- | --- |\n";
  md.precision(3);
  for (std::size_t a = 0; a < arms.size(); ++a)
    md << "| " << a << " | " << arms[a].root.x() << ", " << arms[a].root.z() << " | " << arms[a].length << " | "
       << arms[a].turn.angle() * 180 / std::numbers::pi << " | " << arms[a].tip.size() << " |\n";
  figures::write(args, "fig22.md", md.str());
  std::cout << md.str();

  figures::expect(unglued.crossing.pairs == 0 && left_unglued.arm_pairs.empty(),
                  "Fig. 22: on the unglued mesh all collided arms of quintupleTorus.obj separate when pulled straight: 0 "
                  "self-intersecting triangle pairs after (input: " + std::to_string(before.pairs) + ")");
  figures::expect(unglued.most_inverted == 0 && unglued.unconverged == 0,
                  "no tet of the unglued mesh of quintupleTorus.obj inverts at any step; Newton converges at every step");
  figures::expect(shared_unglued == 0, "no mesh vertex of the unglued mesh carries the ends of two arms");
  figures::expect(glued.crossing.pairs > 0 && glued.inverted > 0,
                  "the glued baseline under the same load keeps " + std::to_string(glued.crossing.pairs) +
                      " self-intersecting pairs (" + std::to_string(left_glued.arm_pairs.size()) +
                      " pairs of arms) and inverts " + std::to_string(glued.inverted) + " tets");

  figures::write(args, "fig22_quintuple_input.obj", dim3::format_obj(input));
  figures::write(args, "fig22_unglued_dropped.obj", dim3::format_obj(unglued.surface));
  figures::write(args, "fig22_glued_dropped.obj", dim3::format_obj(glued.surface));
  const render::View view{30, 18, 1};  // the model's up is y
  figures::input_picture(args, "fig22_quintuple_input.png", "quintupleTorus.obj, collided faces red", input, before, view);
  figures::deformed_outputs(args, "fig22_unglued_dropped", "unglued, plate held, arms pulled straight", unglued.surface,
                             unglued.crossing, in.unglued, unglued.positions, mesh.mesh.reference, view);
  figures::deformed_outputs(args, "fig22_glued_dropped", "glued baseline, same load", glued.surface, glued.crossing,
                             in.glued.mesh, glued.positions, {}, view);
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "fig_22_quintuple_drop");
    figures::describe("Fig. 22 (right)",
                      "we simulate the output mesh using FEM: the mesh is capable of separating all of the collided "
                      "cylinders (a naively glued mesh holds them together).");
    const std::filesystem::path obj = std::filesystem::path(IMM_SHARED_DATA_DIR) / "3d" / "quintupleTorus.obj";
    const std::filesystem::path veg = std::filesystem::path(IMM_SHARED_DATA_DIR) / "tet" / "quintupleTorus.veg";
    if (!args.quick && std::filesystem::exists(obj) && std::filesystem::exists(veg)) {
      run_real(args, obj.string(), veg.string());
      return;
    }
    if (!args.quick) std::cout << "fig_22: " << obj.string() << " or " << veg.string() << " absent: the generated model\n";
    const int n = args.quick ? 8 : 12;
    const dim3::Surface input = dim3::quintuple_torus(n);
    const figures::Crossings before = figures::crossings(input);
    figures::expect(before.pairs > 0, "Fig. 22: the cylinders collide with the tori and each other");
    int parts = 0;
    const std::vector<int> part = figures::surface_parts(input, parts);
    figures::expect(parts == 12, "the generated quintuple torus: 5 tori and 7 cylinders, 12 solids");

    dim3::MeshOptions options;
    options.resolution = args.quick ? 14 : 20;
    const auto [im, mesh, in] = figures::immerse_and_mesh(input, options, "the quintuple torus");

    // Held: the five tori (the first five parts). Free: the seven cylinders. Ground 4.5 below
    // the ring (z = 0): the tilted cylinders (half-length 1.6 + caps) land with their tops below
    // the tori (|z| < 0.4).
    std::vector<std::size_t> held;
    std::vector<bool> held_part(input.vertices.size(), false);
    for (std::size_t v = 0; v < input.vertices.size(); ++v)
      if (part[v] < 5) {
        held.push_back(v);
        held_part[v] = true;
      }
    deform::FemOptions fem;  // E = 1e4, nu = 0.3, density 1
    fem.time_step = args.quick ? 1.0 / 20 : 1.0 / 30;
    fem.gravity = Eigen::Vector3d(0, 0, -9.81);
    fem.ground_normal = Eigen::Vector3d(0, 0, 1);
    fem.ground_offset = -4.5;
    fem.step_tolerance = 1e-4;  // 1e-4 of an edge: far below what a picture or the facts resolve
    const int steps = args.quick ? 24 : 36;  // 1.2 s: free fall to the ground takes 0.94 s
    const figures::Dropped unglued = figures::drop(in.unglued, in.unglued_embedding, input, held, held_part, fem, steps);
    const figures::Dropped glued = figures::drop(in.glued.mesh, in.glued_embedding, input, held, held_part, fem, steps);
    std::cout << "pairs between a torus and a cylinder after the drop (exact): unglued " << unglued.held_free_pairs
              << ", glued " << glued.held_free_pairs << "; mean drop of the cylinders: unglued " << unglued.free_drop
              << ", glued " << glued.free_drop << '\n';
    figures::expect(unglued.held_free_pairs == 0,
                    "Fig. 22: on the unglued mesh all seven collided cylinders drop out of the tori: 0 torus-cylinder "
                    "triangle pairs intersect after the simulation");
    figures::expect(unglued.most_inverted == 0, "no tet of the unglued mesh inverts at any step of the simulation");
    figures::expect(glued.held_free_pairs > 0,
                    "the glued baseline holds the cylinders in the tori: " + std::to_string(glued.held_free_pairs) +
                        " torus-cylinder triangle pairs still intersect");
    figures::expect(unglued.free_drop > 3.0 && glued.free_drop < 0.5,
                    "the unglued cylinders fall to the ground (mean drop > 3), the glued ones hang in the tori (< 0.5)");

    figures::write(args, "fig22_quintuple_input.obj", dim3::format_obj(input));
    figures::write(args, "fig22_unglued_dropped.obj", dim3::format_obj(unglued.surface));
    figures::write(args, "fig22_glued_dropped.obj", dim3::format_obj(glued.surface));
    const render::View view{30, 18, 2};
    figures::input_picture(args, "fig22_quintuple_input.png", "the quintuple torus, collided faces red", input, before, view);
    figures::deformed_outputs(args, "fig22_unglued_dropped", "unglued, tori held, dropped under gravity",
                               unglued.surface, unglued.crossing, in.unglued, unglued.positions, mesh.mesh.reference, view);
    figures::deformed_outputs(args, "fig22_glued_dropped", "glued baseline, same simulation", glued.surface,
                               glued.crossing, in.glued.mesh, glued.positions, {}, view);

    std::ostringstream md;
    md << "# Fig. 22: the quintuple torus under FEM\n\n"
       << "- input: quintuple_torus(" << n << "), " << input.triangle_count() << " triangles, " << before.pairs
       << " self-intersecting triangle pairs (5 tori, 7 cylinders)\n"
       << "- unglued mesh: " << in.unglued.element_count() << " tets, " << in.unglued.vertex_count()
       << " vertices; glued baseline: " << in.glued.mesh.element_count() << " tets, " << in.glued.mesh.vertex_count()
       << " vertices (resolution " << options.resolution << ")\n"
       << "- dynamic FEM (implicit Euler, h = " << fem.time_step << " s, " << steps
       << " steps, co-rotational E = 1e4, nu = 0.3, density 1, gravity 9.81 along -z, ground plane z = " << fem.ground_offset
       << "): the five tori held, the cylinders free\n\n"
       << kTableHead << row("unglued", unglued) << row("glued", glued);

    md << "\n- CPU seconds per step (median / max, the process: all threads): unglued " << step_times(unglued) << ", glued "
       << step_times(glued) << "\n\nThe paper's quintupleTorus.obj on its .veg runs in full mode when ../shared/data "
       << "is present.\n";
    figures::write(args, "fig22.md", md.str());
    std::cout << md.str();
  });
}
