// slamkit info FILE: what a pose-graph file holds and whether it is usable.
//
// Prints format, dimension, vertex/edge counts (odometry = pose–pose edges between
// consecutive ids, the other pose–pose edges are loop closures), connected components,
// fixed vertices, EQUIV count, the health of the information matrices, the initial chi2
// (g2o's definition, at the file's estimates) and the load time. --json writes the same.
#include <algorithm>
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"

namespace slamkit::cli {

namespace {

struct InfoOptions {
  std::string file;
  std::string json;
  std::string format = "auto";
  bool repair_information = false;
  bool allow_unknown_tags = false;
};

struct EdgeCounts {
  std::size_t odometry = 0, loop_closures = 0, landmark = 0;
};

EdgeCounts count_edges(const PoseGraph& g) {
  EdgeCounts c;
  for (const GraphEdge& e : g.edges) {
    const bool pose_pose = e.kind == EdgeKind::kPose2Pose2 || e.kind == EdgeKind::kPose3Pose3;
    if (!pose_pose) {
      ++c.landmark;
    } else if (is_odometry(e)) {
      ++c.odometry;
    } else {
      ++c.loop_closures;
    }
  }
  return c;
}

std::string fixed_digits(double v, int digits) {
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

void run_info(const InfoOptions& o) {
  check_outputs({{&o.json, "--json"}});
  PoseGraphReadOptions read;
  read.format = parse_pose_graph_format(o.format);
  read.repair_information = o.repair_information;
  read.unknown_tags_as_warnings = o.allow_unknown_tags;
  PoseGraphReadReport report;
  const Stopwatch watch;
  const PoseGraph g = load_pose_graph(o.file, read, &report);
  const double load_time = watch.seconds();
  for (const std::string& w : report.warnings) std::cerr << "slamkit: warning: " << w << "\n";

  const EdgeCounts edges = count_edges(g);
  const InformationHealth& h = report.information;
  const double chi2 = total_chi2(g);
  const std::size_t components = count_connected_components(g);

  nlohmann::json j;
  j["file"] = o.file;
  j["format"] = to_string(report.format);
  j["dimension"] = g.dimension();
  j["vertices"] = g.vertices().size();
  j["poses"] = g.num_poses();
  j["landmarks"] = g.num_points();
  j["edges"] = g.edges.size();
  j["odometry_edges"] = edges.odometry;
  j["loop_closures"] = edges.loop_closures;
  j["landmark_edges"] = edges.landmark;
  j["components"] = components;
  j["fixed_vertices"] = g.fixed.size();
  j["equivalences"] = g.equivalences.size();
  j["sensor_offsets"] = g.sensor_offsets.size();
  const auto calibrated = std::count_if(g.edges.begin(), g.edges.end(), [](const GraphEdge& e) { return e.calibrated.has_value(); });
  j["calibration_vertices"] = g.calibration.vertices.size();
  j["calibrated_edges"] = calibrated;
  j["edges_only"] = report.edges_only;
  j["estimates_from_odometry"] = report.completed_estimates;
  j["positive_definite_information_edges"] = h.positive_definite;
  j["singular_information_edges"] = h.singular;
  j["indefinite_information_edges"] = h.indefinite;
  j["not_symmetric_information_edges"] = h.not_symmetric;
  j["non_finite_information_edges"] = h.not_finite;
  j["first_bad_information_line"] = h.first_bad_line;
  j["repaired_information_edges"] = report.repaired_information;
  j["initial_chi2"] = chi2;
  j["load_time_s"] = load_time;
  j["warnings"] = report.warnings;
  j["options"] = {{"format", o.format},
                  {"repair_information", o.repair_information},
                  {"allow_unknown_tags", o.allow_unknown_tags}};
  if (!o.json.empty()) write_json(o.json, j);
  if (o.json == "-") return;  // JSON on stdout: nothing else there

  std::ostream& out = std::cout;
  auto row = [&out](const std::string& label, const std::string& value) {
    out << "  " << std::left << std::setw(20) << label << value << "\n";
  };
  out << "pose graph " << o.file << "\n";
  row("format", std::string(to_string(report.format)) + ", " + std::to_string(g.dimension()) + "D");
  row("vertices", std::to_string(g.vertices().size()) + " (" + std::to_string(g.num_poses()) + " poses, " +
                      std::to_string(g.num_points()) + " landmarks)");
  row("edges", std::to_string(g.edges.size()) + " (" + std::to_string(edges.odometry) + " odometry, " +
                   std::to_string(edges.loop_closures) + " loop closures, " + std::to_string(edges.landmark) +
                   " landmark)");
  row("components", std::to_string(components));
  row("fixed vertices", std::to_string(g.fixed.size()));
  row("equivalences", std::to_string(g.equivalences.size()) + " (EQUIV)");
  if (!g.sensor_offsets.empty()) row("sensor offsets", std::to_string(g.sensor_offsets.size()));
  if (calibrated > 0 || !g.calibration.vertices.empty())
    row("calibration", std::to_string(g.calibration.vertices.size()) + " vertices, " + std::to_string(calibrated) +
                           " calibrated edges (docs/calibration.md)");
  if (report.edges_only) {
    row("estimates", "edges-only file: " + std::to_string(report.completed_estimates) +
                         " vertices initialized by odometry composition");
  }
  row("information", std::to_string(h.positive_definite) + " positive definite, " + std::to_string(h.singular) +
                         " singular, " + std::to_string(h.indefinite) + " indefinite, " +
                         std::to_string(h.not_symmetric) + " not symmetric, " + std::to_string(h.not_finite) +
                         " not finite");
  if (h.bad() > 0) {
    row("", "first one on line " + std::to_string(h.first_bad_line) +
                (o.repair_information ? "; " + std::to_string(report.repaired_information) + " projected to the PSD cone"
                                      : "; --repair-information projects them to the PSD cone"));
  }
  row("initial chi2", fixed_digits(chi2, 10) + (o.repair_information && report.repaired_information > 0
                                                     ? " (with repaired information)"
                                                     : ""));
  row("load time", fixed_digits(load_time, 3) + " s");
  row("options", "--format " + o.format + (o.repair_information ? " --repair-information" : "") +
                     (o.allow_unknown_tags ? " --allow-unknown-tags" : ""));
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand("info", "Summarize a pose-graph file (g2o, TORO, GTSAM EDGE3)");
  cmd->add_option("file", o->file, "pose-graph file")->required();
  cmd->add_option("--json", o->json, "also write the summary as JSON to this file ('-': stdout only)");
  cmd->add_option("--format", o->format, "input format instead of detecting it")
      ->check(CLI::IsMember({"auto", "g2o", "toro", "gtsam"}, CLI::ignore_case));
  cmd->add_flag("--repair-information", o->repair_information,
                "project information matrices that are not positive definite to the PSD cone");
  cmd->add_flag("--allow-unknown-tags", o->allow_unknown_tags, "skip unknown tags with a warning instead of failing");
  cmd->callback([o]() { run_info(*o); });
}

}  // namespace slamkit::cli
