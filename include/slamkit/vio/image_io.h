// Image input/output for the front end and the rendered simulator (PNG through OpenCV, which
// only the vio module links), and the EuRoC/ASL folder layout of an image sequence:
//
//   DIR/mav0/cam0/data/<t_ns>.png                  grayscale images (8 bit)
//   DIR/mav0/cam0/data.csv                         "#timestamp [ns],filename"
//   DIR/mav0/labels0/data/<t_ns>.png               per-pixel labels (8 bit: 0 static, k object id)
//   DIR/mav0/labels0/data.csv                      same stamps as cam0
//   DIR/mav0/imu0/data.csv                         "#timestamp [ns],w_x,w_y,w_z [rad s^-1],a_x,a_y,a_z [m s^-2]"
//   DIR/mav0/state_groundtruth_estimate0/data.csv  IMU pose, velocity, gyro and accel biases at
//                                                  every IMU stamp (EuRoC columns)
//   DIR/times.txt                                  one frame stamp [ns] a line (ORB-SLAM3 style)
//   DIR/objects.csv                                moving objects: id, path, speed, time window
// (the CLI adds the calibration files and a TUM ground truth at the frame stamps; see
// docs/simulator.md). Stamps are t_ns = round(t · 1e9). Readers are strict: errors name the
// file, the line and the field (InputError).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "slamkit/core/imu_measurement.h"
#include "slamkit/core/trajectory.h"
#include "slamkit/sim/gray_image.h"
#include "slamkit/sim/rendered_scene.h"
#include "slamkit/sim/visual_inertial_sim.h"

namespace slamkit {

/// Writes an 8-bit grayscale PNG; throws InputError(path, 0, "image", ...) if it cannot.
void write_png(const std::string& path, const GrayImage& image);
/// Reads a PNG (or any image OpenCV reads) as 8-bit grayscale (colour is converted); throws
/// InputError if the file is missing or not an image.
GrayImage read_png(const std::string& path);

std::int64_t stamp_ns(double t);

struct ImageSequenceFrame {
  std::int64_t t_ns = 0;
  double t = 0.0;              ///< t_ns · 1e-9
  std::string image_path;      ///< absolute or relative to the working directory
  std::string label_path;      ///< empty without labels0
};

struct ImageSequence {
  std::string root;
  std::vector<ImageSequenceFrame> frames;
  std::vector<ImuMeasurement> imu;  ///< empty without imu0
  Trajectory groundtruth;           ///< IMU poses; empty without state_groundtruth_estimate0
  bool has_labels() const { return !frames.empty() && !frames.front().label_path.empty(); }
};

/// Reads the layout above (cam0 required; labels0, imu0 and the ground truth when present).
/// Throws InputError naming the file, line and field on a malformed csv, stamps that do not
/// increase, a missing image or label file, or labels whose stamps differ from cam0's.
ImageSequence read_image_sequence(const std::string& dir);

/// Writes a sequence in the layout above, frame by frame.
class ImageSequenceWriter {
 public:
  /// Creates the folders and probes that a file can be written; throws InputError (field
  /// "images") at once if not, before any rendering.
  explicit ImageSequenceWriter(std::string dir);
  const std::string& root() const { return root_; }
  /// Writes cam0 (and labels0 unless labels is null) PNGs of the frame at time t.
  void add_frame(double t, const GrayImage& image, const GrayImage* labels);
  void write_imu(const std::vector<SimImuSample>& imu) const;
  void write_groundtruth(const std::vector<SimState>& states) const;
  void write_objects(const RenderedScene& scene) const;
  /// Writes the cam0/labels0 data.csv files and times.txt of the frames added so far.
  void finish() const;

 private:
  std::string root_;
  std::vector<std::int64_t> stamps_;
  bool labels_ = false;
};

}  // namespace slamkit
