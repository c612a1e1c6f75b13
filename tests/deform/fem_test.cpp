// FEM (deform/fem.h) with known answers, for triangles and tetrahedra alike: the patch test
// (an affine boundary motion gives the same affine map inside), rigid invariance of the
// material, conservation of momentum without external forces, a drop onto the ground without
// inverted elements.
#include <gtest/gtest.h>

#include <algorithm>
#include <type_traits>

#include "deform/fem.h"
#include "grid.h"

namespace imm::deform {
namespace {

template <class T>
class Fem : public testing::Test {};
using Dims = testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(Fem, Dims);

template <int D>
std::vector<Eigen::Index> boundary_vertices(const SimplexMesh<D>& mesh) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if ((mesh.vertices.row(v).array() <= 0.0).any() || (mesh.vertices.row(v).array() >= 1.0).any()) out.push_back(v);
  return out;
}

TYPED_TEST(Fem, PatchTestAffineBoundaryGivesAffineInterior) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> fixed = boundary_vertices<D>(mesh);
  ASSERT_LT(static_cast<Eigen::Index>(fixed.size()), mesh.vertex_count());
  const Material material{.youngs_modulus = 100.0, .poisson_ratio = 0.35, .density = 1.0};
  const FemData<D> data = fem_precompute<D>(mesh, fixed, material);
  ASSERT_TRUE(data.ok()) << data.error;
  // A stretch, a shear and a rotation: x -> A x + c.
  Eigen::Matrix<double, D, D> a = test::test_rotation<D>(3);
  a.col(0) *= 1.3;
  a(0, D - 1) += 0.2;
  const Eigen::Matrix<double, 1, D> c = Eigen::Matrix<double, 1, D>::Constant(0.1);
  const Eigen::MatrixXd expected = (mesh.vertices * a.transpose()).rowwise() + c;
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(fixed.size()), D);
  for (std::size_t k = 0; k < fixed.size(); ++k) targets.row(static_cast<Eigen::Index>(k)) = expected.row(fixed[k]);
  Eigen::MatrixXd x = mesh.vertices;
  FemOptions options;
  options.material = material;
  options.step_tolerance = 1e-12;
  const FemReport report = fem_static<D>(data, x, targets, options);
  ASSERT_TRUE(report.error.empty()) << report.error;
  EXPECT_TRUE(report.converged);
  EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-9);
  // Equilibrium: the elastic force vanishes at every free vertex.
  const Eigen::MatrixXd forces = elastic_forces<D>(data, x, material);
  std::vector<char> is_fixed(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (Eigen::Index v : fixed) is_fixed[static_cast<std::size_t>(v)] = 1;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if (!is_fixed[static_cast<std::size_t>(v)]) EXPECT_LT(forces.row(v).norm(), 1e-8) << "vertex " << v;
}

TYPED_TEST(Fem, RigidMotionsCostNothingAndForcesBalance) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(3);
  const Material material;
  const FemData<D> data = fem_precompute<D>(mesh, {}, material);
  const Eigen::MatrixXd moved = (mesh.vertices * test::test_rotation<D>(1).transpose()).rowwise() +
                                Eigen::Matrix<double, 1, D>::Constant(2.0);
  EXPECT_LT(elastic_energy<D>(data, moved, material), 1e-20);
  EXPECT_LT(elastic_forces<D>(data, moved, material).cwiseAbs().maxCoeff(), 1e-9);
  // Any deformation: the internal forces sum to zero (translation invariance of the energy).
  Eigen::MatrixXd wobbly = mesh.vertices;
  for (Eigen::Index v = 0; v < wobbly.rows(); ++v) wobbly.row(v).array() += 0.05 * std::sin(3.0 * v);
  const Eigen::MatrixXd forces = elastic_forces<D>(data, wobbly, material);
  EXPECT_GT(forces.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_LT(forces.colwise().sum().cwiseAbs().maxCoeff(), 1e-9 * forces.cwiseAbs().maxCoeff() * forces.rows());
}

TYPED_TEST(Fem, MomentumIsConservedWithoutExternalForces) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(3);
  FemOptions options;
  options.material = {.youngs_modulus = 500.0, .poisson_ratio = 0.3, .density = 2.0};
  options.time_step = 0.01;
  options.step_tolerance = 1e-13;
  const FemData<D> data = fem_precompute<D>(mesh, {}, options.material);
  FemState<D> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
  for (Eigen::Index v = 0; v < state.velocities.rows(); ++v)
    for (int a = 0; a < D; ++a) state.velocities(v, a) = std::cos(1.3 * v + a) + 0.2 * a;
  const auto momentum = [&] { return Eigen::VectorXd(data.mass.transpose() * state.velocities); };
  const Eigen::VectorXd before = momentum();
  ASSERT_GT(before.norm(), 0.1);
  for (int step = 0; step < 5; ++step) {
    const FemReport report = fem_step<D>(data, state, Eigen::MatrixXd(0, D), options);
    EXPECT_TRUE(report.converged) << "step " << step;
  }
  EXPECT_LT((momentum() - before).norm(), 1e-9 * before.norm());
  EXPECT_TRUE(inverted_elements<D>(state.positions, mesh.elements).empty());
}

TYPED_TEST(Fem, DropOntoTheGroundNeverInverts) {
  constexpr int D = TypeParam::value;
  SimplexMesh<D> mesh = test::bar_grid<D>(6, 1.5, 2, 0.5);
  mesh.vertices.col(D - 1).array() += 0.3;  // above the ground at height 0 (last axis up)
  FemOptions options;
  options.material = {.youngs_modulus = 2e3, .poisson_ratio = 0.4, .density = 1.0};
  options.time_step = 0.02;
  options.gravity = Eigen::VectorXd::Zero(D);
  options.gravity[D - 1] = -9.81;
  options.ground_normal = Eigen::VectorXd::Unit(D, D - 1);
  options.ground_offset = 0.0;
  options.ground_stiffness = 1e5;
  const FemData<D> data = fem_precompute<D>(mesh, {}, options.material);
  FemState<D> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
  double lowest = 1e9;
  for (int step = 0; step < 40; ++step) {
    const FemReport report = fem_step<D>(data, state, Eigen::MatrixXd(0, D), options);
    ASSERT_TRUE(report.error.empty()) << report.error;
    ASSERT_TRUE(inverted_elements<D>(state.positions, mesh.elements).empty()) << "step " << step;
    lowest = std::min(lowest, state.positions.col(D - 1).minCoeff());
  }
  // It fell (the top started at 0.8) and the ground held it: penetration a few millimetres.
  EXPECT_LT(state.positions.col(D - 1).maxCoeff(), 0.6);
  EXPECT_GT(lowest, -0.02);
}

// Newton on the exact Hessian (with dR/dF) converges quadratically: a bent step, which the
// fixed-rotation co-rotational stiffness needs 50 iterations for (rate ~0.75), takes a handful, and
// the last steps shrink quadratically. Also checked: it is a minimum (the free vertices' net
// force is in balance with inertia and gravity), so the few iterations are not an early stop.
TYPED_TEST(Fem, NewtonConvergesQuadraticallyOnABentStep) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> fixed = test::vertices_where<D>(mesh, 0, 0.0, 1.0);  // both end faces
  FemOptions options;
  options.material = {.youngs_modulus = 1e4, .poisson_ratio = 0.3, .density = 1.0};
  options.time_step = 1.0 / 30.0;
  options.gravity = Eigen::VectorXd::Zero(D);
  options.gravity[D - 1] = -9.81;
  const FemData<D> data = fem_precompute<D>(mesh, fixed, options.material);
  ASSERT_TRUE(data.ok()) << data.error;
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(fixed.size()), D);
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    Eigen::Matrix<double, 1, D> p = mesh.vertices.row(fixed[k]);
    if (p(0) > 0.5) p(D - 1) += 0.5;  // the far end face moved by half the bar's length
    targets.row(static_cast<Eigen::Index>(k)) = p;
  }
  FemState<D> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
  const Eigen::MatrixXd start = state.positions;
  const FemReport report = fem_step<D>(data, state, targets, options);
  ASSERT_TRUE(report.error.empty()) << report.error;
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.newton_iterations, 10);
  // First-order optimality of the incremental potential, checked through elastic_forces:
  // M (x - x_n - h v_n) / h^2 = f_elastic + M g at every free vertex.
  const Eigen::MatrixXd forces = elastic_forces<D>(data, state.positions, options.material);
  std::vector<char> is_fixed(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (Eigen::Index v : fixed) is_fixed[static_cast<std::size_t>(v)] = 1;
  const double h = options.time_step;
  double largest = 0.0, residual = 0.0;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    if (is_fixed[static_cast<std::size_t>(v)]) continue;
    const Eigen::Matrix<double, 1, D> inertia = data.mass[v] * (state.positions.row(v) - start.row(v)) / (h * h);
    const Eigen::Matrix<double, 1, D> gravity = data.mass[v] * options.gravity.transpose();
    largest = std::max(largest, forces.row(v).norm());
    residual = std::max(residual, (inertia - forces.row(v) - gravity).norm());
  }
  ASSERT_GT(largest, 1.0);
  EXPECT_LT(residual, 1e-8 * largest);
}

// The Newton systems solved by conjugate gradients preconditioned with an earlier factorization
// (kept across the steps in a FemSolver) give the minimizer that a factorization every Newton
// iteration gives, to the Newton tolerance, in about as many Newton iterations: a step solved
// less accurately than pcg_tolerance says would stop early at a wrong state (the step test
// takes a short inexact step for convergence) or need more iterations. The handles jump in
// every step, and a cap of 4 PCG iterations makes the first iterations after each jump
// refactor: the decision to refactor is exercised too, not only the preconditioned solves.
TYPED_TEST(Fem, ReusedFactorizationGivesTheRefactoredMinimum) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> fixed = test::vertices_where<D>(mesh, 0, 0.0, 1.0);  // both end faces
  FemOptions options;
  options.material = {.youngs_modulus = 1e4, .poisson_ratio = 0.3, .density = 1.0};
  options.time_step = 1.0 / 30.0;
  options.gravity = Eigen::VectorXd::Zero(D);
  options.gravity[D - 1] = -9.81;
  options.step_tolerance = 1e-10;
  options.max_pcg_iterations = 4;
  FemOptions direct = options;
  direct.max_pcg_iterations = 0;
  const FemData<D> data = fem_precompute<D>(mesh, fixed, options.material);
  ASSERT_TRUE(data.ok()) << data.error;
  FemState<D> reference{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)}, reused = reference;
  FemSolver solver;
  int newton_reference = 0, newton_reused = 0, factorizations = 0, pcg = 0;
  for (int step = 1; step <= 6; ++step) {
    Eigen::MatrixXd targets(static_cast<Eigen::Index>(fixed.size()), D);
    for (std::size_t k = 0; k < fixed.size(); ++k) {
      Eigen::Matrix<double, 1, D> p = mesh.vertices.row(fixed[k]);
      if (p(0) > 0.5) p(D - 1) += 0.1 * std::min(step, 4);  // up by 0.1 per step, then held
      targets.row(static_cast<Eigen::Index>(k)) = p;
    }
    const FemReport a = fem_step<D>(data, reference, targets, direct);
    const FemReport b = fem_step<D>(data, reused, targets, options, &solver);
    ASSERT_TRUE(a.error.empty() && b.error.empty()) << a.error << b.error;
    EXPECT_TRUE(a.converged && b.converged) << "step " << step;
    EXPECT_EQ(a.pcg_iterations, 0);
    EXPECT_GE(a.factorizations, a.newton_iterations);
    newton_reference += a.newton_iterations;
    newton_reused += b.newton_iterations;
    factorizations += b.factorizations;
    pcg += b.pcg_iterations;
    EXPECT_LT((reused.positions - reference.positions).cwiseAbs().maxCoeff(), options.step_tolerance * data.edge_length)
        << "step " << step;
  }
  // The reused path did reuse (fewer factorizations than Newton iterations) and did refactor.
  EXPECT_GT(pcg, 0);
  EXPECT_LT(factorizations, newton_reused);
  EXPECT_GT(factorizations, 1);
  EXPECT_LE(newton_reused, newton_reference + 6);
}

// The element loops run on several threads (value, gradient, Newton matrix); every sum is taken
// in element order, so a simulation is the same bit for bit on 1, 2 or 3 threads. The mesh has
// more elements than one assembly chunk (4096), so chunk boundaries and each thread's range of
// vertices are crossed; the load (a moved end, gravity, the ground) makes every term count.
TYPED_TEST(Fem, ResultDoesNotDependOnTheThreadCount) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::bar_grid<D>(D == 2 ? 80 : 20, 2.0, D == 2 ? 40 : 10);
  ASSERT_GT(mesh.element_count(), 4096);
  const std::vector<Eigen::Index> fixed = test::vertices_where<D>(mesh, 0, 0.0, 1e9);  // the end x = 0
  ASSERT_FALSE(fixed.empty());
  Eigen::MatrixXd targets = mesh.vertices(fixed, Eigen::all);
  targets.col(D - 1).array() += 0.2;
  FemOptions options;
  options.time_step = 1.0 / 30.0;
  options.gravity = Eigen::VectorXd::Zero(D);
  options.gravity[D - 1] = -9.81;
  options.ground_normal = Eigen::VectorXd::Unit(D, D - 1);
  options.ground_offset = 0.05;  // above the mesh's lowest vertices: the penalty acts at once
  const FemData<D> data = fem_precompute<D>(mesh, fixed, options.material);
  ASSERT_TRUE(data.ok()) << data.error;
  std::vector<FemState<D>> states;
  std::vector<FemReport> reports;
  for (unsigned threads : {1u, 2u, 3u}) {
    options.threads = threads;
    FemState<D> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
    FemSolver solver;
    FemReport report;
    for (int step = 0; step < 3; ++step) {
      report = fem_step<D>(data, state, targets, options, &solver);
      ASSERT_TRUE(report.error.empty()) << report.error;
    }
    states.push_back(state);
    reports.push_back(report);
  }
  EXPECT_GT(reports[0].newton_iterations, 1);
  for (std::size_t k = 1; k < states.size(); ++k) {
    EXPECT_EQ(states[k].positions, states[0].positions) << (k + 1) << " threads";
    EXPECT_EQ(states[k].velocities, states[0].velocities) << (k + 1) << " threads";
    EXPECT_EQ(reports[k].objective, reports[0].objective) << (k + 1) << " threads";
    EXPECT_EQ(reports[k].newton_iterations, reports[0].newton_iterations);
  }
}

// fem_prepare does a simulation's once-only work (the Newton matrix's pattern and symbolic
// analysis) before its first step, and says what it cost: the first step given the prepared
// solver does no analysis of its own and ends where a step with a fresh solver ends, bit for bit.
TYPED_TEST(Fem, PreparedSolverDoesTheAnalysisBeforeTheFirstStep) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(4);
  const std::vector<Eigen::Index> fixed = test::vertices_where<D>(mesh, 0, 0.0, 1.0);
  Eigen::MatrixXd targets = mesh.vertices(fixed, Eigen::all);
  for (Eigen::Index k = 0; k < targets.rows(); ++k)
    if (targets(k, 0) > 0.5) targets(k, D - 1) += 0.2;
  const FemData<D> data = fem_precompute<D>(mesh, fixed, Material{});
  ASSERT_TRUE(data.ok()) << data.error;
  FemOptions options;
  options.time_step = 1.0 / 30.0;
  FemSolver prepared;
  const FemReport setup = fem_prepare<D>(data, prepared);
  EXPECT_GT(setup.seconds.analysis, 0.0);
  EXPECT_EQ(setup.unknowns, (mesh.vertex_count() - static_cast<Eigen::Index>(fixed.size())) * D);
  EXPECT_GT(setup.nonzeros, setup.unknowns);
  EXPECT_EQ(setup.newton_iterations, 0);
  EXPECT_EQ(setup.factorizations, 0);
  FemState<D> a{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)}, b = a;
  const FemReport step = fem_step<D>(data, a, targets, options, &prepared);
  FemSolver fresh;
  const FemReport unprepared = fem_step<D>(data, b, targets, options, &fresh);
  EXPECT_EQ(step.seconds.analysis, 0.0);
  EXPECT_GT(unprepared.seconds.analysis, 0.0);
  EXPECT_EQ(step.unknowns, setup.unknowns);
  EXPECT_EQ(step.nonzeros, setup.nonzeros);
  EXPECT_TRUE(step.converged);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(step.objective, unprepared.objective);
}

// A sudden handle jump: the linear prediction (FemOptions::predict_fixed_motion) spreads the
// handles' motion over the free vertices before Newton starts, which then reaches the same
// minimizer (to the Newton tolerance) in fewer iterations, the prediction's solve counted as
// one; in dynamics and in statics, through the factor-every-iteration and the reused-factor paths.
TYPED_TEST(Fem, LinearPredictionOfAHandleJumpSavesNewtonIterations) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::bar_grid<D>(D == 2 ? 24 : 12, 3.0, D == 2 ? 8 : 4);
  const std::vector<Eigen::Index> fixed = test::vertices_where<D>(mesh, 0, 0.0, 3.0);  // both end faces
  Eigen::MatrixXd targets = mesh.vertices(fixed, Eigen::all);
  for (Eigen::Index k = 0; k < targets.rows(); ++k)
    if (targets(k, 0) > 1.5) targets(k, D - 1) += 0.6;  // the far end jumps by a fifth of the length
  const FemData<D> data = fem_precompute<D>(mesh, fixed, Material{});
  ASSERT_TRUE(data.ok()) << data.error;
  for (int pcg : {0, 20}) {
    FemOptions predicted;
    predicted.time_step = 1.0 / 30.0;
    predicted.max_pcg_iterations = pcg;
    FemOptions plain = predicted;
    plain.predict_fixed_motion = false;
    FemState<D> a{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)}, b = a;
    const FemReport with = fem_step<D>(data, a, targets, predicted), without = fem_step<D>(data, b, targets, plain);
    ASSERT_TRUE(with.error.empty() && without.error.empty()) << with.error << without.error;
    EXPECT_TRUE(with.converged && without.converged);
    EXPECT_LT(with.newton_iterations, without.newton_iterations) << "dynamics, pcg " << pcg;
    EXPECT_LT((a.positions - b.positions).cwiseAbs().maxCoeff(), predicted.step_tolerance * data.edge_length);
    Eigen::MatrixXd x = mesh.vertices, y = mesh.vertices;
    const FemReport with_static = fem_static<D>(data, x, targets, predicted);
    const FemReport without_static = fem_static<D>(data, y, targets, plain);
    ASSERT_TRUE(with_static.error.empty() && without_static.error.empty());
    EXPECT_TRUE(with_static.converged && without_static.converged);
    EXPECT_LT(with_static.newton_iterations, without_static.newton_iterations) << "statics, pcg " << pcg;
    EXPECT_LT((x - y).cwiseAbs().maxCoeff(), predicted.step_tolerance * data.edge_length);
  }
}

// Every vertex a handle: the step is the handles' motion, with nothing to solve (it crashed on
// the empty Newton system).
TYPED_TEST(Fem, EveryVertexFixedMovesToTheTargets) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(2);
  std::vector<Eigen::Index> all(static_cast<std::size_t>(mesh.vertex_count()));
  for (std::size_t v = 0; v < all.size(); ++v) all[v] = static_cast<Eigen::Index>(v);
  const FemData<D> data = fem_precompute<D>(mesh, all, Material{});
  ASSERT_TRUE(data.ok()) << data.error;
  const Eigen::MatrixXd targets = (mesh.vertices.array() + 0.5).matrix();
  FemState<D> state{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
  const FemReport report = fem_step<D>(data, state, targets, FemOptions{});
  EXPECT_TRUE(report.error.empty()) << report.error;
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(state.positions, targets);
  Eigen::MatrixXd x = mesh.vertices;
  EXPECT_TRUE(fem_static<D>(data, x, targets, FemOptions{}).error.empty());
  EXPECT_EQ(x, targets);
}

TYPED_TEST(Fem, StaticProblemWithALooseComponentIsRefused) {
  constexpr int D = TypeParam::value;
  const SimplexMesh<D> mesh = test::unit_grid<D>(1);
  const FemData<D> data = fem_precompute<D>(mesh, {}, Material{});
  Eigen::MatrixXd x = mesh.vertices;
  const FemReport report = fem_static<D>(data, x, Eigen::MatrixXd(0, D), FemOptions{});
  EXPECT_FALSE(report.error.empty());
}

}  // namespace
}  // namespace imm::deform
