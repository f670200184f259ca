// Bindings of slamkit/io: pose-graph files (g2o, TORO, GTSAM) and trajectory files (TUM,
// EuRoC/ASL, KITTI, slamkit), from paths or strings. Readers raise slamkit.InputError naming
// the file, line and field.
#include <sstream>

#include "bind_common.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/io/pose_graph_source.h"
#include "slamkit/io/trajectory_io.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit::python {
namespace {

PoseGraphReadOptions read_options(const std::string& format, bool unknown_tags_as_warnings, bool repair,
                                  bool complete) {
  PoseGraphReadOptions o;
  o.format = parse_pose_graph_format(format);
  o.unknown_tags_as_warnings = unknown_tags_as_warnings;
  o.repair_information = repair;
  o.complete_estimates = complete;
  return o;
}

py::object graph_with_report(PoseGraph g, const PoseGraphReadReport& r, bool with_report) {
  if (!with_report) return py::cast(std::move(g));
  return py::make_tuple(std::move(g), r);
}

TrajectoryFormat trajectory_format(const std::string& path, const std::string& format) {
  return format == "auto" ? detect_trajectory_format(path) : parse_trajectory_format(format);
}

}  // namespace

void init_io(py::module_& m) {
  py::class_<PoseGraphReadReport>(m, "PoseGraphReadReport", "What a reader found besides the graph.")
      .def_property_readonly("format", [](const PoseGraphReadReport& r) { return std::string(to_string(r.format)); })
      .def_readonly("warnings", &PoseGraphReadReport::warnings)
      .def_readonly("information", &PoseGraphReadReport::information)
      .def_readonly("repaired_information", &PoseGraphReadReport::repaired_information)
      .def_readonly("edges_only", &PoseGraphReadReport::edges_only)
      .def_readonly("completed_estimates", &PoseGraphReadReport::completed_estimates);

  m.def(
      "read_pose_graph",
      [](const std::string& path, const std::string& format, bool unknown_tags_as_warnings, bool repair,
         bool complete, bool with_report) {
        PoseGraphReadReport report;
        PoseGraph g;
        {
          py::gil_scoped_release release;
          g = read_pose_graph(path, read_options(format, unknown_tags_as_warnings, repair, complete), &report);
        }
        return graph_with_report(std::move(g), report, with_report);
      },
      py::arg("path"), py::arg("format") = "auto", py::arg("unknown_tags_as_warnings") = false,
      py::arg("repair_information") = false, py::arg("complete_estimates") = true, py::arg("with_report") = false,
      "Reads a g2o / TORO / GTSAM file (format 'auto' | 'g2o' | 'toro' | 'gtsam'). Returns the PoseGraph, or "
      "(graph, PoseGraphReadReport) with with_report=True. Raises InputError naming file, line and field.");
  m.def(
      "load_pose_graph",
      [](const std::string& spec, const std::string& format, bool unknown_tags_as_warnings, bool repair) {
        py::gil_scoped_release release;
        return load_pose_graph(spec, read_options(format, unknown_tags_as_warnings, repair, true));
      },
      py::arg("spec"), py::arg("format") = "auto", py::arg("unknown_tags_as_warnings") = false,
      py::arg("repair_information") = false,
      "What `slamkit optimize FILE` loads: a pose-graph file or a generated graph 'sim:sphere', "
      "'sim:manhattan?seed=3', 'sim:calib2d?laps=2', ...");
  m.def(
      "pose_graph_from_string",
      [](const std::string& text, const std::string& source, const std::string& format, bool unknown_tags_as_warnings,
         bool repair) {
        std::istringstream in(text);
        return read_pose_graph(in, source, read_options(format, unknown_tags_as_warnings, repair, true));
      },
      py::arg("text"), py::arg("source") = "<string>", py::arg("format") = "auto",
      py::arg("unknown_tags_as_warnings") = false, py::arg("repair_information") = false,
      "Parses pose-graph text; source names it in errors (and its extension hints the format).");
  m.def(
      "write_pose_graph",
      [](const PoseGraph& g, const std::string& path, const std::string& format) {
        std::vector<std::string> warnings;
        write_pose_graph(g, path, parse_pose_graph_format(format), &warnings);
        return warnings;
      },
      py::arg("graph"), py::arg("path"), py::arg("format") = "auto",
      "Writes the graph (format 'auto': from the extension); returns the warnings (dropped elements).");
  m.def(
      "pose_graph_to_string",
      [](const PoseGraph& g, const std::string& format) {
        return pose_graph_to_string(g, parse_pose_graph_format(format));
      },
      py::arg("graph"), py::arg("format") = "g2o", "The text write_pose_graph would write.");
  m.def(
      "pose_graph_format_from_extension",
      [](const std::string& path) { return std::string(to_string(format_from_extension(path))); }, py::arg("path"),
      "'.g2o' -> 'g2o', '.graph' -> 'toro', '.txt' -> 'gtsam', else 'auto'.");

  m.def(
      "read_trajectory",
      [](const std::string& path, const std::string& format) {
        const TrajectoryFormat f = trajectory_format(path, format);
        py::gil_scoped_release release;
        return read_trajectory(path, f);
      },
      py::arg("path"), py::arg("format") = "auto",
      "Reads a trajectory file: 'auto' (by content / .csv), 'tum', 'euroc' (or 'asl'), 'kitti', 'slamkit'.");
  m.def(
      "trajectory_from_string",
      [](const std::string& text, const std::string& format, const std::string& source) {
        std::istringstream in(text);
        return read_trajectory(in, source, parse_trajectory_format(format));
      },
      py::arg("text"), py::arg("format") = "tum", py::arg("source") = "<string>",
      "Parses trajectory text; source names it in errors.");
  m.def(
      "write_trajectory",
      [](const std::string& path, const Trajectory& t, const std::string& format) {
        write_trajectory(path, t, parse_trajectory_format(format));
      },
      py::arg("path"), py::arg("trajectory"), py::arg("format") = "tum",
      "Writes a trajectory file ('tum', 'euroc', 'kitti', 'slamkit').");
  m.def(
      "trajectory_to_string",
      [](const Trajectory& t, const std::string& format) {
        std::ostringstream out;
        write_trajectory(out, t, parse_trajectory_format(format));
        return out.str();
      },
      py::arg("trajectory"), py::arg("format") = "tum", "The text write_trajectory would write.");
  m.def(
      "detect_trajectory_format",
      [](const std::string& path) { return std::string(to_string(detect_trajectory_format(path))); },
      py::arg("path"), "Guesses a trajectory file's format: 'tum', 'euroc', 'kitti' or 'slamkit'.");
}

}  // namespace slamkit::python
