#include "slamkit/io/visual_inertial_sequence_io.h"

#include "slamkit/io/kalibr_calibration.h"
#include "slamkit/io/trajectory_io.h"

namespace slamkit {

SequenceSimulation simulate_visual_inertial_sequence(const std::string& spec, const std::string& data_root,
                                                     VisualInertialSimOptions options, double knot_spacing) {
  SequenceSimulation out;
  out.sequence = resolve_visual_inertial_sequence(spec, visual_inertial_data_root(data_root));
  const CameraCalibration cam = read_kalibr_camchain(out.sequence.camchain.string()).at(0);
  const ImuCalibration imu = read_kalibr_imu(out.sequence.imu.string());
  options.imu_noise = ImuNoiseDensities{imu.gyroscope_noise_density, imu.gyroscope_random_walk,
                                        imu.accelerometer_noise_density, imu.accelerometer_random_walk};
  options.imu_rate = imu.update_rate;
  options.mask_radius_px = out.sequence.mask_radius_px;
  const Trajectory path = read_trajectory(out.sequence.trajectory.string());
  BSplineFitOptions fit;
  fit.knot_spacing = knot_spacing;
  out.spline = BSplineTrajectory::fit(path, fit, &out.fit);
  out.options = options;
  out.sim = simulate_visual_inertial(*out.spline, cam.model, cam.T_cam_imu, options);
  out.sim.source = spec;
  out.camera_name = cam.name;
  out.distortion_model = cam.distortion_model;
  out.width = cam.width, out.height = cam.height;
  return out;
}

}  // namespace slamkit
