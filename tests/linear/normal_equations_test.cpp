#include "slamkit/linear/normal_equations.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "slamkit/factors/pose_graph_problem.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit {
namespace {

PoseGraphProblem small_sphere() {
  PoseGraphSimOptions o;
  o.world = "sphere";
  o.rings = 6;
  o.poses_per_ring = 8;
  o.translation_sigma = 0.2;
  o.rotation_sigma = 0.05;
  PoseGraph g = generate_pose_graph(o);
  PoseGraphProblemOptions po;
  po.kernel = make_robust_kernel("cauchy", 2.0);
  return build_pose_graph_problem(g, po);
}

TEST(NormalEquations, MatchesDenseJacobianProducts) {
  PoseGraphProblem p = small_sphere();
  NormalEquations ne(p.graph, p.values);
  const ThreadPool pool(1);
  const double cost = ne.linearize(p.values, pool);
  EXPECT_NEAR(cost, p.graph.cost(p.values), 1e-9 * cost);
  // Dense J and r from Factor::linearize, columns of free variables only.
  const int n = ne.dim();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(0, n);
  Eigen::VectorXd r(0);
  for (const auto& f : p.graph) {
    const int m = f->residual_dim();
    std::vector<const double*> params;
    std::vector<std::vector<double>> jac(f->keys().size(), std::vector<double>(m * 6));
    std::vector<double*> jp;
    for (std::size_t k = 0; k < f->keys().size(); ++k) {
      params.push_back(p.values.params(p.values.index_of(f->keys()[k])));
      jp.push_back(jac[k].data());
    }
    std::vector<double> res(m);
    f->linearize(params.data(), res.data(), jp.data());
    Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(m, n);
    for (std::size_t k = 0; k < f->keys().size(); ++k) {
      const int b = ne.block_of_variable(p.values.index_of(f->keys()[k]));
      if (b >= 0) rows.middleCols(ne.hessian().block_start(b), 6) = Eigen::Map<Eigen::MatrixXd>(jac[k].data(), m, 6);
    }
    J.conservativeResize(J.rows() + m, n);
    J.bottomRows(m) = rows;
    r.conservativeResize(r.size() + m);
    r.tail(m) = Eigen::Map<Eigen::VectorXd>(res.data(), m);
  }
  const Eigen::MatrixXd H = J.transpose() * J;
  EXPECT_LT((ne.hessian().to_dense() - H).norm(), 1e-9 * H.norm());
  EXPECT_LT((ne.gradient() - J.transpose() * r).norm(), 1e-9 * std::max(1.0, ne.gradient().norm()));
  EXPECT_TRUE(ne.hessian_diagonal().isApprox(H.diagonal()));
}

TEST(NormalEquations, BitIdenticalForAnyThreadCount) {
  PoseGraphProblem p = small_sphere();
  NormalEquations a(p.graph, p.values), b(p.graph, p.values);
  const double ca = a.linearize(p.values, ThreadPool(1));
  const double cb = b.linearize(p.values, ThreadPool(4));
  EXPECT_EQ(ca, cb);
  ASSERT_EQ(a.hessian().values().size(), b.hessian().values().size());
  EXPECT_EQ(0, std::memcmp(a.hessian().values().data(), b.hessian().values().data(),
                           sizeof(double) * a.hessian().values().size()));
  EXPECT_EQ(0, std::memcmp(a.gradient().data(), b.gradient().data(), sizeof(double) * a.gradient().size()));
}

TEST(NormalEquations, EvaluateLeavesTheSystemAndAssembleCompletesIt) {
  PoseGraphProblem p = small_sphere();
  const ThreadPool pool(2);
  NormalEquations ne(p.graph, p.values), reference(p.graph, p.values);
  EXPECT_THROW(ne.assemble(pool), std::logic_error);  // nothing evaluated yet
  ne.linearize(p.values, pool);
  const std::vector<double> H_at_x = ne.hessian().values();
  const Eigen::VectorXd g_at_x = ne.gradient();

  // A candidate: its cost, while H and g stay those of x (a rejected step keeps them).
  Values candidate = p.values;
  const Eigen::VectorXd delta = Eigen::VectorXd::Constant(ne.dim(), 0.01);
  ne.retract(p.values, delta.data(), candidate, pool);
  const double c = ne.evaluate(candidate, pool);
  EXPECT_NEAR(c, p.graph.cost(candidate), 1e-12 * c);
  EXPECT_EQ(ne.hessian().values(), H_at_x);
  EXPECT_EQ(ne.gradient(), g_at_x);

  // Accepted: assemble() gives exactly what a full linearization at the candidate gives.
  ne.assemble(pool);
  EXPECT_EQ(reference.linearize(candidate, ThreadPool(1)), c);
  EXPECT_EQ(ne.hessian().values(), reference.hessian().values());
  EXPECT_EQ(ne.gradient(), reference.gradient());

  candidate.params(1)[0] = std::numeric_limits<double>::quiet_NaN();  // a point that does not evaluate
  EXPECT_TRUE(std::isnan(ne.evaluate(candidate, pool)));
  EXPECT_THROW(ne.assemble(pool), std::logic_error);
}

TEST(NormalEquations, RejectsProblemsWithoutFreeVariables) {
  PoseGraphProblem p = small_sphere();
  for (std::size_t i = 0; i < p.values.size(); ++i) p.values.set_fixed(p.values.key(i));
  EXPECT_THROW(NormalEquations(p.graph, p.values), InputError);
}

}  // namespace
}  // namespace slamkit
