// Bindings of slamkit/vio: the sliding-window visual-inertial estimator (docs/vio.md) on a
// simulated run, as `slamkit vio --sim` does: a named TUM-VI / EuRoC sequence simulated in
// memory (or a file written by `slamkit simulate --vi -o`), then the estimator with its options
// and the DVI weighting of issue 13 (α(M), θ). The estimate and the truth come back as
// Trajectory objects, one sample per frame, with the per-frame timings and static ratios.
#include <algorithm>
#include <filesystem>

#include "bind_common.h"
#include "slamkit/io/visual_inertial_sequence_io.h"
#include "slamkit/io/visual_inertial_sim_io.h"
#include "slamkit/vio/vio_sim_runner.h"

namespace slamkit::python {
namespace {

/// What a Python user reads of a run: the trajectories and the summary numbers of `slamkit vio`.
struct VioResult {
  Trajectory estimate, truth;
  std::size_t frames = 0, keyframes = 0, visual_frames_dropped = 0;
  double features_per_frame = 0.0, initialized_at_s = 0.0, wall_time_s = 0.0, cpu_time_s = 0.0;
  double sequence_duration_s = 0.0, realtime_factor = 0.0;
  double solve_ms_mean = 0.0, marginalization_ms_mean = 0.0;
  double static_ratio_mean = 1.0, static_ratio_min = 1.0;
  std::string startup_method, startup_message;
  double startup_rotation_rms_deg = 0.0, startup_scale_rel_sigma = 0.0;
  int startup_dynamic_left_out = 0;
};

VioResult to_result(const VioRunResult& r) {
  VioResult out;
  out.estimate = r.estimate, out.truth = r.truth;
  out.frames = r.frames.size(), out.keyframes = r.keyframes;
  out.features_per_frame = r.features_per_frame, out.initialized_at_s = r.initialized_at_s;
  out.wall_time_s = r.wall_time_s, out.cpu_time_s = r.cpu_time_s, out.sequence_duration_s = r.sequence_duration_s;
  out.realtime_factor = r.sequence_duration_s / std::max(1e-9, r.wall_time_s);
  out.startup_method = r.startup.method, out.startup_message = r.startup.message;
  out.startup_rotation_rms_deg = r.startup.rotation_rms_deg, out.startup_dynamic_left_out = r.startup.dynamic_left_out;
  out.startup_scale_rel_sigma = r.startup.scale_rel_sigma;
  double solve = 0.0, marg = 0.0, m_sum = 0.0;
  for (const FrameEstimate& e : r.frames) {
    solve += e.solve_ms, marg += e.marginalization_ms, m_sum += e.static_ratio;
    out.static_ratio_min = std::min(out.static_ratio_min, e.static_ratio);
    out.visual_frames_dropped += e.visual_dropped;
  }
  const double n = static_cast<double>(std::max<std::size_t>(1, r.frames.size()));
  out.solve_ms_mean = solve / n, out.marginalization_ms_mean = marg / n, out.static_ratio_mean = m_sum / n;
  return out;
}

}  // namespace

void init_vio(py::module_& m) {
  py::class_<VisualInertialSim>(m, "VisualInertialSim",
                                "A simulated visual-inertial run: IMU samples, camera frames with feature observations "
                                "(static or on moving groups) and the true states.")
      .def_readonly("source", &VisualInertialSim::source)
      .def_readonly("seed", &VisualInertialSim::seed)
      .def_property_readonly("dynamic", [](const VisualInertialSim& s) { return std::string(to_string(s.dynamic)); })
      .def_property_readonly("camera_model", [](const VisualInertialSim& s) { return s.camera->model_name(); })
      .def_property_readonly("num_frames", [](const VisualInertialSim& s) { return s.frames.size(); })
      .def_property_readonly("num_imu_samples", [](const VisualInertialSim& s) { return s.imu.size(); })
      .def_property_readonly("duration", [](const VisualInertialSim& s) { return summarize(s).duration; })
      .def_property_readonly("static_ratio_min", [](const VisualInertialSim& s) { return summarize(s).static_ratio_min; })
      .def("__repr__", [](const VisualInertialSim& s) {
        return "VisualInertialSim(source='" + s.source + "', dynamic='" + to_string(s.dynamic) +
               "', frames=" + std::to_string(s.frames.size()) + ", imu_samples=" + std::to_string(s.imu.size()) + ")";
      });

  py::class_<VioResult>(m, "VioResult", "The estimate and truth of a VIO run (one sample per frame) and its summary.")
      .def_readonly("estimate", &VioResult::estimate)
      .def_readonly("truth", &VioResult::truth)
      .def_readonly("frames", &VioResult::frames, "frames estimated after the start-up window")
      .def_readonly("keyframes", &VioResult::keyframes)
      .def_readonly("visual_frames_dropped", &VioResult::visual_frames_dropped, "DVI: frames with M < theta")
      .def_readonly("features_per_frame", &VioResult::features_per_frame)
      .def_readonly("initialized_at_s", &VioResult::initialized_at_s, "from the start of the run")
      .def_readonly("wall_time_s", &VioResult::wall_time_s)
      .def_readonly("cpu_time_s", &VioResult::cpu_time_s, "process CPU time of the run")
      .def_readonly("sequence_duration_s", &VioResult::sequence_duration_s)
      .def_readonly("realtime_factor", &VioResult::realtime_factor, "sequence duration / wall time")
      .def_readonly("solve_ms_mean", &VioResult::solve_ms_mean, "window solve per frame")
      .def_readonly("marginalization_ms_mean", &VioResult::marginalization_ms_mean)
      .def_readonly("static_ratio_mean", &VioResult::static_ratio_mean, "mean over frames of M = static / all")
      .def_readonly("static_ratio_min", &VioResult::static_ratio_min)
      .def_readonly("startup_method", &VioResult::startup_method)
      .def_readonly("startup_message", &VioResult::startup_message)
      .def_readonly("startup_rotation_rms_deg", &VioResult::startup_rotation_rms_deg,
                    "the accepted start-up window's SfM rotations against the gyroscope (RMS, deg)")
      .def_readonly("startup_scale_rel_sigma", &VioResult::startup_scale_rel_sigma,
                    "the accepted start-up window's scale standard deviation / scale")
      .def_readonly("startup_dynamic_left_out", &VioResult::startup_dynamic_left_out,
                    "dynamic-flagged observations the start-up SfM left out (DVI)")
      .def("__repr__", [](const VioResult& r) {
        return "VioResult(frames=" + std::to_string(r.frames) + ", keyframes=" + std::to_string(r.keyframes) +
               ", realtime_factor=" + std::to_string(r.realtime_factor) + ")";
      });

  m.def(
      "simulate_visual_inertial",
      [](const std::string& sequence, double duration, const std::string& dynamic, std::uint64_t seed,
         const std::string& data) {
        require_finite(duration, "duration");
        if (duration < 0) throw py::value_error("duration: must be >= 0 (0: the whole sequence)");
        VisualInertialSimOptions o;
        o.seed = seed;
        o.dynamic = parse_dynamic_level(dynamic);
        o.duration = duration;
        py::gil_scoped_release release;
        if (is_visual_inertial_sequence_name(sequence)) return simulate_visual_inertial_sequence(sequence, data, o).sim;
        if (std::filesystem::exists(sequence)) return read_visual_inertial_sim(sequence);
        throw InputError(sequence, 0, "sequence", "neither a named sequence (room1..room4, euroc:V1_01, ...) nor a "
                                                  "simulation file");
      },
      py::arg("sequence"), py::arg("duration") = 0.0, py::arg("dynamic") = "none", py::arg("seed") = 1,
      py::arg("data") = "",
      "A simulated visual-inertial run of a named sequence ('room1'..'room4', 'euroc:V1_01', 'euroc:V1_02', "
      "'euroc:V2_03') from its real path and calibration under data (default $SLAMKIT_DATA), or the file "
      "`slamkit simulate --vi -o` wrote. dynamic: 'none' | 'low' | 'high' (moving groups); duration 0: whole.");

  m.def(
      "run_vio",
      [](const VisualInertialSim& sim, int window_size, int max_iterations, int threads, const std::string& solver,
         bool dvi, const std::string& alpha, const std::string& theta, bool ground_truth_start, bool dvi_startup,
         double max_rotation_rms_deg, double max_scale_rel_sigma) {
        if (window_size < 2) throw py::value_error("window_size: must be >= 2");
        if (max_iterations < 1) throw py::value_error("max_iterations: must be >= 1");
        if (threads < 1 || threads > 256) throw py::value_error("threads: must be in [1, 256]");
        if (solver != "dense" && solver != "sparse") throw py::value_error("solver: 'dense' or 'sparse'");
        SlidingWindowOptions so;
        so.window_size = window_size;
        so.max_iterations = max_iterations;
        so.num_threads = threads;
        so.dense_solver = solver == "dense";
        so.dvi.enabled = dvi;
        parse_dvi_alpha(alpha, &so.dvi);
        parse_dvi_theta(theta, &so.dvi);
        VioStartupOptions startup;
        startup.use_ground_truth = ground_truth_start;
        startup.dvi_startup = dvi_startup;
        if (!(max_rotation_rms_deg >= 0.0)) throw py::value_error("max_rotation_rms_deg: must be >= 0 (0: off)");
        startup.alignment.max_rotation_rms_deg = max_rotation_rms_deg;
        if (!(max_scale_rel_sigma >= 0.0)) throw py::value_error("max_scale_rel_sigma: must be >= 0 (0: off)");
        startup.alignment.max_scale_rel_sigma = max_scale_rel_sigma;
        py::gil_scoped_release release;
        return to_result(run_vio_on_sim(sim, so, {}, startup));
      },
      py::arg("sim"), py::arg("window_size") = 10, py::arg("max_iterations") = 4, py::arg("threads") = 1,
      py::arg("solver") = "dense", py::arg("dvi") = false, py::arg("alpha") = "M^2", py::arg("theta") = "0.5",
      py::arg("ground_truth_start") = false, py::arg("dvi_startup") = true, py::arg("max_rotation_rms_deg") = 2.0,
      py::arg("max_scale_rel_sigma") = 0.25,
      "The sliding-window visual-inertial estimator on a simulated run, as `slamkit vio --sim`: starts with the "
      "visual-inertial initializer (no ground truth after the first frame) unless ground_truth_start. dvi=True "
      "weighs a frame's visual factors by alpha(M) ('1', 'M', 'M^k') and drops them when M < theta (a number in "
      "[0, 1] or 'adaptive'); dvi=False is the baseline. With dvi and dvi_startup the start-up SfM leaves out "
      "dynamic-flagged features; a start-up window whose SfM rotations disagree with the gyroscope by more than "
      "max_rotation_rms_deg (RMS; 0: off), or whose scale has a relative standard deviation above "
      "max_scale_rel_sigma (0: off), is refused. Results are identical for any thread count.");
}

}  // namespace slamkit::python
