// Bindings of the landmark-SLAM filters (EKF, EIF, SEIF, entropy-SEIF, FastSLAM 1.0/2.0) on
// the 2-D landmark world of the consistency benchmark: worlds and simulated runs as arrays, a
// filter stepped from Python, and the Monte-Carlo consistency summary of `slamkit filter`.
#include <cmath>

#include "bind_common.h"
#include "slamkit/eval/filter_consistency.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/geometry/lie_math.h"
#include "slamkit/io/landmark_map_io.h"
#include "slamkit/sim/landmark_sim.h"

namespace slamkit::python {
namespace {

std::vector<Eigen::Vector2d> to_points(const py::handle& a, const char* what) {
  const RowMatrixXd m = to_matrix(a, -1, 2, what);
  std::vector<Eigen::Vector2d> v;
  for (Eigen::Index i = 0; i < m.rows(); ++i) v.emplace_back(m(i, 0), m(i, 1));
  return v;
}

py::array_t<double> points_array(const std::vector<Eigen::Vector2d>& v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t{2}});
  auto u = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i) u(i, 0) = v[i].x(), u(i, 1) = v[i].y();
  return a;
}

// Observations as an N×3 array [id, range, bearing] (id < 0: unknown association).
std::vector<RangeBearing> to_observations(const py::handle& a) {
  const RowMatrixXd m = to_matrix(a, -1, 3, "observations");
  std::vector<RangeBearing> z;
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    if (m(i, 0) != std::floor(m(i, 0))) throw py::value_error("observations: the id column must hold integers");
    z.push_back({static_cast<int>(m(i, 0)), m(i, 1), m(i, 2)});
  }
  return z;
}

py::array_t<double> observations_array(const std::vector<RangeBearing>& z) {
  py::array_t<double> a({static_cast<py::ssize_t>(z.size()), py::ssize_t{3}});
  auto u = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < z.size(); ++i) u(i, 0) = z[i].id, u(i, 1) = z[i].range, u(i, 2) = z[i].bearing;
  return a;
}

// The options `slamkit filter` uses: the simulator's vehicle and sensor noise.
LandmarkFilterOptions filter_options(const LandmarkSimOptions& sim, const std::string& association, int active,
                                     int particles, std::uint64_t seed) {
  if (active < 1 || particles < 1) throw py::value_error("active_landmarks and particles must be >= 1");
  LandmarkFilterOptions fo;
  fo.motion = std::make_shared<BicycleModel>(sim.wheelbase, sim.sigma_v, sim.sigma_steer);
  fo.sensor = RangeBearingModel(sim.sigma_range, sim.sigma_bearing);
  fo.association.method = parse_association_method(association);
  fo.association.candidate_range = sim.max_range + 10.0;
  fo.active_landmarks = active;
  fo.particles = particles;
  fo.seed = seed;
  return fo;
}

LandmarkSimOptions sim_options(int steps, int laps) {
  if (steps < 0 || laps < 1) throw py::value_error("steps must be >= 0 and laps >= 1");
  LandmarkSimOptions s;
  s.max_steps = steps;
  s.laps = laps;
  return s;
}

}  // namespace

void init_filters(py::module_& m) {
  m.def(
      "generate_landmark_world",
      [](int num_landmarks, std::uint64_t seed) {
        if (num_landmarks < 1 || num_landmarks > 1000000) throw py::value_error("num_landmarks must be in 1..1000000");
        std::vector<Eigen::Vector2d> l, w;
        generate_landmark_world(num_landmarks, seed, &l, &w);
        return py::make_tuple(points_array(l), points_array(w));
      },
      py::arg("num_landmarks"), py::arg("seed") = 1,
      "A closed route of waypoints with landmarks along it (`slamkit filter --world generated:N`): "
      "(landmarks N×2, waypoints W×2).");
  m.def(
      "read_landmark_map",
      [](const std::string& path) {
        const LandmarkMap map = read_landmark_map(path);
        return py::make_tuple(points_array(map.landmarks), points_array(map.waypoints));
      },
      py::arg("path"), "A Bailey simulator map (webmap, densemap, ...): (landmarks, waypoints); InputError names file:line.");
  m.def(
      "simulate_landmark_run",
      [](const py::handle& landmarks, const py::handle& waypoints, std::uint64_t seed, int steps, int laps) {
        const LandmarkSimRun run =
            simulate_landmark_run(to_points(landmarks, "landmarks"), to_points(waypoints, "waypoints"),
                                  sim_options(steps, laps), seed);
        py::array_t<double> truth({static_cast<py::ssize_t>(run.steps.size()), py::ssize_t{3}});
        py::array_t<double> controls({static_cast<py::ssize_t>(run.steps.size()), py::ssize_t{2}});
        auto t = truth.mutable_unchecked<2>();
        auto c = controls.mutable_unchecked<2>();
        py::list scans;
        for (std::size_t k = 0; k < run.steps.size(); ++k) {
          const LandmarkSimStep& s = run.steps[k];
          for (int j = 0; j < 3; ++j) t(k, j) = s.true_pose(j);
          c(k, 0) = s.v, c(k, 1) = s.steer;
          scans.append(s.observed ? py::object(observations_array(s.observations)) : py::object(py::none()));
        }
        py::dict d;
        d["true_poses"] = truth, d["controls"] = controls, d["observations"] = scans, d["dt"] = LandmarkSimOptions{}.dt;
        return d;
      },
      py::arg("landmarks"), py::arg("waypoints"), py::arg("seed") = 1, py::arg("steps") = 0, py::arg("laps") = 1,
      "One seeded run of the simulator: true_poses K×3 after each control, controls K×2 (noisy v, steering), "
      "observations (per step None, or an N×3 array [id, range, bearing]) and dt.");

  py::class_<LandmarkFilter, std::shared_ptr<LandmarkFilter>>(m, "LandmarkFilter",
                                                              "A landmark-SLAM filter (made by make_landmark_filter).")
      .def_property_readonly("name", &LandmarkFilter::name)
      .def(
          "predict",
          [](LandmarkFilter& f, double v, double turn, double dt) {
            for (double x : {v, turn, dt}) require_finite(x, "control");
            if (!(dt > 0)) throw py::value_error("dt must be > 0");
            f.predict({v, turn, dt});
          },
          py::arg("v"), py::arg("turn"), py::arg("dt"), "Motion update: speed, steering (or yaw rate), time step.")
      .def(
          "update", [](LandmarkFilter& f, const py::handle& z) { f.update(to_observations(z)); }, py::arg("observations"),
          "Measurement update with one scan: an N×3 array [id, range, bearing].")
      .def("pose", &LandmarkFilter::pose, "Pose estimate [x, y, theta].")
      .def("pose_covariance", &LandmarkFilter::pose_covariance, "3×3 marginal covariance of the pose.")
      .def(
          "landmarks",
          [](const LandmarkFilter& f) {
            const std::vector<LandmarkEstimate> l = f.landmarks();
            std::vector<int> ids;
            std::vector<Eigen::Vector2d> means;
            py::array_t<double> cov({static_cast<py::ssize_t>(l.size()), py::ssize_t{2}, py::ssize_t{2}});
            auto u = cov.mutable_unchecked<3>();
            for (std::size_t i = 0; i < l.size(); ++i) {
              ids.push_back(l[i].id), means.push_back(l[i].mean);
              for (int a = 0; a < 2; ++a)
                for (int b = 0; b < 2; ++b) u(i, a, b) = l[i].covariance(a, b);
            }
            return py::make_tuple(to_array(ids), points_array(means), cov);
          },
          "The map: (ids, means N×2, covariances N×2×2).")
      .def("joint_covariance", &LandmarkFilter::joint_covariance, py::arg("landmark_ids"),
           "Covariance of [pose; the listed landmarks] ((3 + 2k) square).")
      .def(
          "last_update",
          [](const LandmarkFilter& f) {
            const UpdateStatistics& s = f.last_update();
            py::dict d;
            d["observations"] = s.observations, d["associated"] = s.associated, d["new_landmarks"] = s.new_landmarks;
            d["rejected"] = s.rejected, d["nis"] = s.nis, d["nis_dof"] = s.nis_dof;
            return d;
          },
          "What the last update did: observations, associated, new_landmarks, rejected, nis, nis_dof.");

  m.def(
      "make_landmark_filter",
      [](const std::string& name, const std::string& association, int active, int particles, std::uint64_t seed) {
        return std::shared_ptr<LandmarkFilter>(
            make_landmark_filter(name, filter_options(LandmarkSimOptions{}, association, active, particles, seed)));
      },
      py::arg("name"), py::arg("association") = "known", py::arg("active_landmarks") = 6, py::arg("particles") = 100,
      py::arg("seed") = 1,
      "ekf | eif | seif | seif-entropy | fastslam1 | fastslam2 with the simulator's vehicle and sensor models "
      "(as `slamkit filter`); association known | nn | jcbb.");
  m.def(
      "run_filter_monte_carlo",
      [](const std::string& name, const py::handle& landmarks, const py::handle& waypoints, int runs,
         std::uint64_t seed, int steps, int laps, const std::string& association, int active, int particles,
         int threads) {
        if (runs < 1) throw py::value_error("runs must be >= 1");
        const LandmarkSimOptions sim = sim_options(steps, laps);
        const LandmarkFilterOptions fo = filter_options(sim, association, active, particles, seed);
        make_landmark_filter(name, fo);  // an unknown name fails before the work
        const std::vector<Eigen::Vector2d> l = to_points(landmarks, "landmarks"), w = to_points(waypoints, "waypoints");
        MonteCarloOptions mc;
        mc.runs = runs, mc.first_seed = seed, mc.threads = threads;
        mc.run.map_nees = fo.association.method == AssociationMethod::kKnown;
        ConsistencySummary s;
        {
          py::gil_scoped_release release;
          s = summarize_consistency(run_monte_carlo([&] { return make_landmark_filter(name, fo); }, l, w, sim, mc));
        }
        py::dict d;
        d["runs"] = s.runs, d["landmarks"] = s.landmarks;
        d["rmse_position"] = s.rmse_position_total, d["rmse_heading"] = s.rmse_heading_total * 180 / kPi;
        d["anees"] = s.anees_mean, d["anees_bounds"] = py::make_tuple(s.anees_lo, s.anees_hi);
        d["fraction_in_bounds"] = s.fraction_in_bounds, d["anis"] = s.anis, d["map_nees"] = s.map_nees;
        py::dict t;
        t["mean"] = s.time_per_step_mean_ms, t["max"] = s.time_per_step_max_ms;
        d["time_per_step_ms"] = t, d["finite"] = s.finite;
        d["time"] = to_array(s.time), d["anees_series"] = to_array(s.anees);
        return d;
      },
      py::arg("name"), py::arg("landmarks"), py::arg("waypoints"), py::arg("runs") = 30, py::arg("seed") = 1,
      py::arg("steps") = 0, py::arg("laps") = 1, py::arg("association") = "known", py::arg("active_landmarks") = 6,
      py::arg("particles") = 100, py::arg("threads") = 0,
      "`slamkit filter` as a dict: N runs (seeds seed..seed+N-1, the same noise for every filter), rmse_position "
      "[m], rmse_heading [deg], anees with its 95% anees_bounds, fraction_in_bounds, anis, map_nees, "
      "time_per_step_ms {mean, max}, and the ANEES series over time.");
}

}  // namespace slamkit::python
