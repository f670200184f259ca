// Peer harness: the same pose-graph files solved by Ceres 2.1 (Debian libceres-dev) in the
// same process as slamkit, so that time ratios are measured on one machine in one run.
// Residuals are g2o's errors (SE2 [t; θ], SE3 [t; q.vec] of Z⁻¹ Xi⁻¹ Xj), so both report
// the same chi2 (Ceres' cost is ½ chi2). Ceres runs single-threaded with SPARSE_NORMAL_CHOLESKY
// (SuiteSparse), its default Levenberg-Marquardt trust region, from (a) the file's estimates
// and (b) slamkit's initialization; slamkit runs its default configuration.
//   ceres_peer [--repeat 3] [--only SUBSTRING] [--out bench/results/ceres_peer.json]
#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench_data.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/linear/blas_runtime.h"

using namespace slamkit;

namespace {

struct Se2Error {
  Se2Error(const SE2& z, const Eigen::Matrix3d& sqrt_info) : z_(z), L_(sqrt_info) {}
  template <class T>
  bool operator()(const T* xi, const T* xj, T* residual) const {
    using std::cos, std::sin;
    const T ci = cos(xi[2]), si = sin(xi[2]);
    const T dx = xj[0] - xi[0], dy = xj[1] - xi[1];
    const T ax = ci * dx + si * dy, ay = -si * dx + ci * dy;  // R_iᵀ (p_j − p_i)
    const double cz = std::cos(z_.theta()), sz = std::sin(z_.theta());
    const T ex = cz * (ax - z_.x()) + sz * (ay - z_.y());
    const T ey = -sz * (ax - z_.x()) + cz * (ay - z_.y());
    T et = xj[2] - xi[2] - z_.theta();
    while (et > T(kPi)) et -= T(2 * kPi);
    while (et <= T(-kPi)) et += T(2 * kPi);
    const T e[3] = {ex, ey, et};
    for (int r = 0; r < 3; ++r) residual[r] = L_(r, 0) * e[0] + L_(r, 1) * e[1] + L_(r, 2) * e[2];
    return true;
  }
  SE2 z_;
  Eigen::Matrix3d L_;
};

struct Se3Error {
  Se3Error(const SE3& z, const Eigen::Matrix<double, 6, 6>& sqrt_info) : z_(z), L_(sqrt_info) {}
  template <class T>
  bool operator()(const T* pi, const T* qi, const T* pj, const T* qj, T* residual) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> Pi(pi), Pj(pj);
    const Eigen::Map<const Eigen::Quaternion<T>> Qi(qi), Qj(qj);
    const Eigen::Quaternion<T> Qzc = z_.rotation().quaternion().conjugate().template cast<T>();
    const Eigen::Quaternion<T> Qa = Qi.conjugate() * Qj;
    const Eigen::Matrix<T, 3, 1> ta = Qi.conjugate() * (Pj - Pi);
    const Eigen::Quaternion<T> Qe = Qzc * Qa;
    const Eigen::Matrix<T, 3, 1> te = Qzc * (ta - z_.translation().cast<T>());
    const T s = Qe.w() < T(0) ? T(-1) : T(1);
    Eigen::Matrix<T, 6, 1> e;
    e << te, s * Qe.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = L_.cast<T>() * e;
    return true;
  }
  SE3 z_;
  Eigen::Matrix<double, 6, 6> L_;
};

struct CeresRun {
  double seconds = 0, chi2 = 0;
  int iterations = 0;
  std::string termination;
};

CeresRun solve_with_ceres(const PoseGraph& g) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = g.vertices().size();
  std::vector<std::array<double, 7>> params(n);  // 2D: x y θ; 3D: p (3) + q (x y z w)
  for (std::size_t i = 0; i < n; ++i) {
    const GraphVertex& v = g.vertices()[i];
    if (v.kind == VertexKind::kPose2) {
      params[i] = {v.pose2.x(), v.pose2.y(), v.pose2.theta()};
    } else {
      const auto& q = v.pose3.rotation().quaternion();
      params[i] = {v.pose3.translation().x(), v.pose3.translation().y(), v.pose3.translation().z(), q.x(), q.y(), q.z(), q.w()};
    }
  }
  ceres::Problem problem;
  ceres::Manifold* quaternion = new ceres::EigenQuaternionManifold;  // owned by the problem
  for (const GraphEdge& e : g.edges) {
    double* a = params[*g.index_of(e.from)].data();
    double* b = params[*g.index_of(e.to)].data();
    const Eigen::MatrixXd L = Eigen::LLT<Eigen::MatrixXd>(e.information).matrixU();
    if (e.kind == EdgeKind::kPose2Pose2) {
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Se2Error, 3, 3, 3>(new Se2Error(e.pose2, L)), nullptr,
                               a, b);
    } else {
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<Se3Error, 6, 3, 4, 3, 4>(new Se3Error(e.pose3, L)), nullptr, a, a + 3, b,
          b + 3);
    }
  }
  if (g.dimension() == 3)
    for (auto& p : params) problem.SetManifold(p.data() + 3, quaternion);
  for (std::int64_t id : gauge_vertices(g)) {
    double* p = params[*g.index_of(id)].data();
    problem.SetParameterBlockConstant(p);
    if (g.dimension() == 3) problem.SetParameterBlockConstant(p + 3);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  options.num_threads = 1;
  options.max_num_iterations = 100;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  CeresRun r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.chi2 = 2.0 * summary.final_cost;
  r.iterations = static_cast<int>(summary.iterations.size()) - 1;
  r.termination = ceres::TerminationTypeToString(summary.termination_type);
  return r;
}

template <class F>
double median_time(int repeat, F run) {
  std::vector<double> t;
  for (int i = 0; i < repeat; ++i) t.push_back(run());
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  reexec_with_better_blas_core(argv);  // Ceres' CHOLMOD runs on the same BLAS kernels as slamkit
  // Ceres calls the same CHOLMOD, whose OpenMP regions use 4 threads whatever OMP_NUM_THREADS
  // says; slamkit makes them serial around its factorizations (1 BLAS thread). Give Ceres the
  // same for the whole run, on the main thread where both solve.
  const SerialOpenMpScope serial_openmp;
  std::string repeat_s = "3", only, out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/ceres_peer.json";
  if (!bench::parse_options(argc, argv, "[--repeat 3] [--only SUBSTRING] [--out FILE]",
                            {{"--repeat", &repeat_s}, {"--only", &only}, {"--out", &out}}))
    return 2;
  const int repeat = bench::int_option("--repeat", repeat_s, 1, 1000);
  const auto root = bench::data_root() / "posegraph";
  if (!std::filesystem::exists(root)) {
    std::fprintf(stderr, "SKIPPED: dataset folder not found: %s\n", root.c_str());
    return 0;
  }
  nlohmann::json results = nlohmann::json::array();
  std::printf("%-32s | %-24s | %-24s | %-24s | %s\n", "file", "slamkit default [s] chi2", "ceres file-init [s] chi2",
              "ceres slamkit-init [s] chi2", "ratios vs ceres (file / slamkit init)");
  for (const bench::Reference& ref : bench::references()) {
    if (!only.empty() && ref.file.find(only) == std::string::npos) continue;
    const PoseGraph original = read_pose_graph((root / ref.file).string());
    PoseGraphResult ours;
    const double t_ours = median_time(repeat, [&] {
      PoseGraph g = original;
      ours = optimize_pose_graph(g);
      return ours.time_total_s;
    });
    CeresRun file_init, our_init;
    const double t_ceres = median_time(repeat, [&] {
      file_init = solve_with_ceres(original);
      return file_init.seconds;
    });
    const double t_ceres_init = median_time(repeat, [&] {
      PoseGraph g = original;
      const InitSummary s = initialize_pose_graph(g, InitMethod::kAuto, gauge_vertices(g));
      our_init = solve_with_ceres(g);
      return s.time_s + our_init.seconds;
    });
    std::printf("%-32s | %8.4f %15.6f | %8.4f %15.6f | %8.4f %15.6f | %.3f / %.3f\n", ref.file.c_str(), t_ours,
                ours.final_chi2, t_ceres, file_init.chi2, t_ceres_init, our_init.chi2, t_ours / t_ceres,
                t_ours / t_ceres_init);
    std::fflush(stdout);
    results.push_back({{"file", ref.file},
                       {"slamkit_seconds", t_ours},
                       {"slamkit_chi2", ours.final_chi2},
                       {"slamkit_iterations", ours.summary.iterations},
                       {"ceres_file_init_seconds", t_ceres},
                       {"ceres_file_init_chi2", file_init.chi2},
                       {"ceres_file_init_iterations", file_init.iterations},
                       {"ceres_file_init_termination", file_init.termination},
                       {"ceres_slamkit_init_seconds", t_ceres_init},
                       {"ceres_slamkit_init_chi2", our_init.chi2},
                       {"ceres_slamkit_init_iterations", our_init.iterations},
                       {"ratio_vs_ceres_file_init", t_ours / t_ceres},
                       {"ratio_vs_ceres_slamkit_init", t_ours / t_ceres_init},
                       {"ceres_version", CERES_VERSION_STRING},
                       {"blas", ours.summary.blas},
                       {"repeat", repeat}});
  }
  std::ofstream(out) << results.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
}
