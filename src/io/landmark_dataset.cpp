#include "slamkit/io/landmark_dataset.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"
#include "slamkit/io/mrclam_odometry.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {
namespace {



std::ifstream open_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  return in;
}

int checked_int(const TextReader& r, std::size_t i, const char* name) {
  const std::int64_t v = r.integer(i, name);
  if (v < -1000000000 || v > 1000000000) r.fail(name, "integer out of range");
  return static_cast<int>(v);
}

void require_time_order(const TextReader& r, double t, double previous, bool has_previous) {
  if (has_previous && t < previous) r.fail("time", "time stamps go backwards");
}

// Bearing in [−π, π] (a datum exactly at −π is accepted and wrapped to +π).
double checked_bearing(const TextReader& r, std::size_t i) {
  const double b = r.number(i, "bearing");
  if (std::abs(b) > kPi + 1e-9) r.fail("bearing", "outside [-pi, pi]");
  return wrap_angle(b);
}

double checked_range(const TextReader& r, std::size_t i) {
  const double v = r.number(i, "range");
  if (!(v > 0)) r.fail("range", "must be positive");
  return v;
}

}  // namespace

std::vector<MrclamSighting> read_mrclam_measurements(std::istream& in, const std::string& source) {
  TextReader r(in, source);
  std::vector<MrclamSighting> out;
  while (r.next_line()) {
    r.expect_fields(4, "measurement (time barcode range bearing)");
    MrclamSighting s{r.number(0, "time"), checked_int(r, 1, "barcode"), checked_range(r, 2),
                     checked_bearing(r, 3)};
    require_time_order(r, s.time, out.empty() ? 0 : out.back().time, !out.empty());
    out.push_back(s);
  }
  return out;
}

std::map<int, int> read_mrclam_barcodes(std::istream& in, const std::string& source) {
  TextReader r(in, source);
  std::map<int, int> barcode_to_subject;
  std::set<int> subjects;
  while (r.next_line()) {
    r.expect_fields(2, "barcode (subject barcode)");
    const int subject = checked_int(r, 0, "subject"), barcode = checked_int(r, 1, "barcode");
    if (subject < 1) r.fail("subject", "must be >= 1");
    if (!subjects.insert(subject).second) r.fail("subject", "listed twice");
    if (!barcode_to_subject.emplace(barcode, subject).second) r.fail("barcode", "listed twice");
  }
  if (barcode_to_subject.empty()) throw InputError(source, 0, "", "no barcodes");
  return barcode_to_subject;
}

std::vector<std::pair<int, Eigen::Vector2d>> read_mrclam_landmarks(std::istream& in,
                                                                   const std::string& source) {
  TextReader r(in, source);
  std::vector<std::pair<int, Eigen::Vector2d>> out;
  std::set<int> seen;
  while (r.next_line()) {
    r.expect_fields(5, "landmark (subject x y x_std y_std)");
    const int subject = checked_int(r, 0, "subject");
    if (!seen.insert(subject).second) r.fail("subject", "listed twice");
    const Eigen::Vector2d p(r.number(1, "x"), r.number(2, "y"));
    if (r.number(3, "x_std") < 0) r.fail("x_std", "negative");
    if (r.number(4, "y_std") < 0) r.fail("y_std", "negative");
    out.emplace_back(subject, p);
  }
  if (out.empty()) throw InputError(source, 0, "", "no landmarks");
  return out;
}

std::vector<VictoriaOdometry> read_victoria_odometry(std::istream& in, const std::string& source) {
  TextReader r(in, source);
  std::vector<VictoriaOdometry> out;
  while (r.next_line()) {
    r.expect_fields(3, "odometry (time_ms speed steering)");
    VictoriaOdometry o{r.number(0, "time") * 1e-3, r.number(1, "speed"), r.number(2, "steering")};
    if (!(std::abs(o.steering) < kPi / 2)) r.fail("steering", "must lie in (-pi/2, pi/2)");
    require_time_order(r, o.time, out.empty() ? 0 : out.back().time, !out.empty());
    out.push_back(o);
  }
  if (out.size() < 2) throw InputError(source, 0, "", "fewer than 2 odometry samples");
  return out;
}

std::vector<VictoriaScan> read_victoria_trees(std::istream& in, const std::string& source) {
  TextReader r(in, source);
  std::vector<VictoriaScan> out;
  while (r.next_line()) {
    r.expect_min_fields(2, "scan (time_ms n (range bearing)*n)");
    VictoriaScan s;
    s.time = r.number(0, "time") * 1e-3;
    const std::int64_t n = r.integer(1, "n");
    if (n < 0 || n > 100000) r.fail("n", "must be in [0, 100000]");
    if (r.num_fields() != static_cast<std::size_t>(2 + 2 * n))
      r.fail("n", "says " + std::to_string(n) + " detections, line has " +
                      std::to_string(r.num_fields()) + " fields (expected " + std::to_string(2 + 2 * n) + ")");
    for (std::int64_t k = 0; k < n; ++k) {
      const std::size_t i = static_cast<std::size_t>(2 + 2 * k);
      s.trees.push_back(RangeBearing{-1, checked_range(r, i), checked_bearing(r, i + 1)});
    }
    require_time_order(r, s.time, out.empty() ? 0 : out.back().time, !out.empty());
    out.push_back(std::move(s));
  }
  return out;
}

void read_victoria_gps(std::istream& in, const std::string& source, std::vector<double>* times,
                       std::vector<Eigen::Vector2d>* positions) {
  TextReader r(in, source);
  times->clear();
  positions->clear();
  while (r.next_line()) {
    r.expect_fields(3, "gps (time_ms x y)");
    const double t = r.number(0, "time") * 1e-3;
    require_time_order(r, t, times->empty() ? 0 : times->back(), !times->empty());
    times->push_back(t);
    positions->emplace_back(r.number(1, "x"), r.number(2, "y"));
  }
}

std::vector<LandmarkDatasetEvent> merge_landmark_events(
    const std::vector<std::pair<double, Eigen::Vector2d>>& commands,
    const std::vector<std::pair<double, std::vector<RangeBearing>>>& scans, int* dropped) {
  std::vector<LandmarkDatasetEvent> events;
  int drop = 0;
  if (commands.size() < 2) throw InputError("", 0, "odometry", "fewer than 2 commands");
  const double t_end = commands.back().first;
  std::size_t k = 0;       // current command: holds over [t_k, t_{k+1})
  double now = commands.front().first;
  auto advance_to = [&](double t) {  // emits controls from `now` to t (t ≤ t_end)
    while (k + 1 < commands.size() && commands[k + 1].first <= t) {
      const double dt = commands[k + 1].first - now;
      if (dt > 0) events.push_back({now, false, Control{commands[k].second.x(), commands[k].second.y(), dt}, {}});
      now = commands[++k].first;
    }
    if (t > now) {
      events.push_back({now, false, Control{commands[k].second.x(), commands[k].second.y(), t - now}, {}});
      now = t;
    }
  };
  for (const auto& [t, obs] : scans) {
    if (t < commands.front().first || t > t_end) {
      drop += static_cast<int>(obs.size());
      continue;
    }
    advance_to(t);
    LandmarkDatasetEvent e;
    e.time = t;
    e.is_scan = true;
    e.observations = obs;
    events.push_back(std::move(e));
  }
  advance_to(t_end);
  if (dropped) *dropped = drop;
  return events;
}

LandmarkDataset read_mrclam_dataset(const std::string& dir, int robot) {
  if (robot < 1 || robot > 5) throw InputError(dir, 0, "robot", "MRCLAM robots are 1..5");
  const std::filesystem::path d(dir);
  auto path = [&](const std::string& f) { return (d / f).string(); };
  LandmarkDataset ds;
  ds.name = "mrclam7-robot" + std::to_string(robot);
  ds.motion_model = "unicycle";
  const MrclamRobotLog log = read_mrclam_robot(dir, robot);  // odometry + Vicon (strict)
  std::ifstream bf = open_file(path("Barcodes.dat"));
  const std::map<int, int> barcodes = read_mrclam_barcodes(bf, path("Barcodes.dat"));
  std::ifstream lf = open_file(path("Landmark_Groundtruth.dat"));
  ds.true_landmarks = read_mrclam_landmarks(lf, path("Landmark_Groundtruth.dat"));
  const std::string meas_path = path("Robot" + std::to_string(robot) + "_Measurement.dat");
  std::ifstream mf = open_file(meas_path);
  const std::vector<MrclamSighting> sightings = read_mrclam_measurements(mf, meas_path);

  // Rows with one stamp form one scan; robot sightings and unknown barcodes are dropped.
  std::vector<std::pair<double, std::vector<RangeBearing>>> scans;
  for (const MrclamSighting& s : sightings) {
    const auto it = barcodes.find(s.barcode);
    if (it == barcodes.end()) {
      ++ds.dropped_unknown_barcodes;
      continue;
    }
    if (it->second <= 5) {
      ++ds.dropped_robot_sightings;
      continue;
    }
    if (scans.empty() || scans.back().first != s.time) scans.push_back({s.time, {}});
    scans.back().second.push_back(RangeBearing{it->second, s.range, s.bearing});
  }
  std::vector<std::pair<double, Eigen::Vector2d>> commands;
  commands.reserve(log.odometry.size());
  for (const MrclamSample& o : log.odometry) commands.push_back({o.t, Eigen::Vector2d(o.a, o.b)});
  ds.events = merge_landmark_events(commands, scans, &ds.dropped_before_start);
  for (const MrclamSample& g : log.groundtruth) {
    ds.truth_times.push_back(g.t);
    ds.truth_poses.emplace_back(g.a, g.b, wrap_angle(g.c));
  }
  const SE2 start = mrclam_groundtruth_at(log, log.odometry.front().t);
  ds.initial_pose = Eigen::Vector3d(start.translation().x(), start.translation().y(), start.theta());
  return ds;
}

LandmarkDataset read_victoria_park(const std::string& dir) {
  const std::filesystem::path d(dir);
  auto path = [&](const std::string& f) { return (d / f).string(); };
  LandmarkDataset ds;
  ds.name = "victoria-park";
  ds.motion_model = "victoria_park";
  std::ifstream of = open_file(path("vp_odometry.txt"));
  const std::vector<VictoriaOdometry> odometry = read_victoria_odometry(of, path("vp_odometry.txt"));
  std::ifstream tf = open_file(path("vp_trees.txt"));
  const std::vector<VictoriaScan> trees = read_victoria_trees(tf, path("vp_trees.txt"));
  std::ifstream gf = open_file(path("vp_gps.txt"));
  read_victoria_gps(gf, path("vp_gps.txt"), &ds.gps_times, &ds.gps_positions);
  std::vector<std::pair<double, Eigen::Vector2d>> commands;
  commands.reserve(odometry.size());
  for (const VictoriaOdometry& o : odometry) commands.push_back({o.time, Eigen::Vector2d(o.speed, o.steering)});
  std::vector<std::pair<double, std::vector<RangeBearing>>> scans;
  scans.reserve(trees.size());
  for (const VictoriaScan& s : trees) scans.push_back({s.time, s.trees});
  ds.events = merge_landmark_events(commands, scans, &ds.dropped_before_start);
  return ds;
}

}  // namespace slamkit
