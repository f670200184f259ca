// Real 2D landmark-SLAM datasets as one time-ordered stream of control and scan events, the
// input every filter of slamkit::filters consumes (datasets/landmark/README.md):
//   MRCLAM Dataset 7 (UTIAS): unicycle odometry (v, ω), range-bearing sightings whose barcodes
//     map to subjects through Barcodes.dat (subjects 1–5 are robots and are dropped, 6–20 are
//     landmarks and become the landmark ids), Vicon ground truth of pose and landmarks.
//   Victoria Park (ACFR): encoder speed and steering every 25 ms (motion model
//     "victoria_park", filters/victoria_park_model.h), laser tree detections without ids
//     (id −1), intermittent GPS (no heading).
// A command holds from its stamp to the next one; a control interval that contains a scan is
// split at the scan, so the filter predicts exactly to the scan time before each update.
// Every reader is strict: InputError names file, line and field.
#pragma once

#include <Eigen/Core>
#include <istream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "slamkit/filters/models.h"

namespace slamkit {

struct LandmarkDatasetEvent {
  double time = 0;      // s, at the start of the control interval / at the scan
  bool is_scan = false;
  Control control;      // control events: v, turn (ω for unicycle, steering for victoria_park), dt
  std::vector<RangeBearing> observations;  // scan events
};

struct LandmarkDataset {
  std::string name;
  std::vector<LandmarkDatasetEvent> events;
  std::vector<double> truth_times;                              // may be empty
  std::vector<Eigen::Vector3d> truth_poses;                     // (x, y, θ), same length
  std::vector<std::pair<int, Eigen::Vector2d>> true_landmarks;  // (id, position), may be empty
  std::vector<double> gps_times;                                // Victoria Park only
  std::vector<Eigen::Vector2d> gps_positions;
  Eigen::Vector3d initial_pose = Eigen::Vector3d::Zero();
  std::string motion_model = "unicycle";  // "unicycle" | "victoria_park"
  int dropped_robot_sightings = 0;        // MRCLAM: sightings of other robots
  int dropped_unknown_barcodes = 0;       // MRCLAM: barcodes not in Barcodes.dat
  int dropped_before_start = 0;           // observations before the first control
};

/// MRCLAM Dataset 7 in `dir`, robot 1..5. The initial pose is the Vicon sample nearest the
/// first odometry stamp; events start there.
LandmarkDataset read_mrclam_dataset(const std::string& dir, int robot);
/// Victoria Park in `dir` (vp_odometry.txt, vp_trees.txt, vp_gps.txt). Times in seconds;
/// initial pose (0, 0, 0).
LandmarkDataset read_victoria_park(const std::string& dir);

// The single-file readers (streams, for tests and fuzzing).

struct MrclamSighting {
  double time;
  int barcode;
  double range, bearing;
};
/// RobotN_Measurement.dat: t barcode range bearing; stamps non-decreasing, range ≥ 0.
std::vector<MrclamSighting> read_mrclam_measurements(std::istream& in, const std::string& source);
/// Barcodes.dat: subject barcode → map barcode → subject (each unique).
std::map<int, int> read_mrclam_barcodes(std::istream& in, const std::string& source);
/// Landmark_Groundtruth.dat: subject x y σx σy → (subject, (x, y)).
std::vector<std::pair<int, Eigen::Vector2d>> read_mrclam_landmarks(std::istream& in,
                                                                   const std::string& source);

struct VictoriaOdometry {
  double time;  // s
  double speed, steering;
};
struct VictoriaScan {
  double time;  // s
  std::vector<RangeBearing> trees;
};
/// vp_odometry.txt: time_ms speed steering (|steering| < π/2, stamps increasing).
std::vector<VictoriaOdometry> read_victoria_odometry(std::istream& in, const std::string& source);
/// vp_trees.txt: time_ms n (range bearing)×n.
std::vector<VictoriaScan> read_victoria_trees(std::istream& in, const std::string& source);
/// vp_gps.txt: time_ms x y.
void read_victoria_gps(std::istream& in, const std::string& source, std::vector<double>* times,
                       std::vector<Eigen::Vector2d>* positions);

/// Builds the event stream from commands (time, v, turn) and scans (both non-decreasing in
/// time): scans before the first command or after the last are dropped (counted in *dropped).
std::vector<LandmarkDatasetEvent> merge_landmark_events(
    const std::vector<std::pair<double, Eigen::Vector2d>>& commands,
    const std::vector<std::pair<double, std::vector<RangeBearing>>>& scans, int* dropped);

}  // namespace slamkit
