// Simulates a named visual-inertial sequence (sim/visual_inertial_sequences.h) in memory: reads
// its path (TUM / EuRoC CSV) and its Kalibr camera and IMU files, fits the cubic B-spline and
// runs the simulator with the sequence's camera, extrinsics, IMU noise and rate, and mask.
// Missing files or fields are InputErrors naming the file (and line).
#pragma once

#include <optional>
#include <string>

#include "slamkit/sim/bspline_trajectory.h"
#include "slamkit/sim/visual_inertial_sequences.h"
#include "slamkit/sim/visual_inertial_sim.h"

namespace slamkit {

struct SequenceSimulation {
  VisualInertialSequence sequence;
  VisualInertialSim sim;
  VisualInertialSimOptions options;          ///< as simulated (sensor fields from the files)
  std::optional<BSplineTrajectory> spline;   ///< the fitted path (the image renderer needs it)
  BSplineFitReport fit;
  std::string camera_name, distortion_model;
  int width = 0, height = 0;
};

/// options: seed, dynamic level, duration (the sensor fields are overwritten from the files).
SequenceSimulation simulate_visual_inertial_sequence(const std::string& spec, const std::string& data_root,
                                                     VisualInertialSimOptions options, double knot_spacing = 0.1);

}  // namespace slamkit
