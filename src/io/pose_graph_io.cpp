#include "slamkit/io/pose_graph_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <istream>
#include <ostream>

#include "pose_graph_format.h"
#include "slamkit/core/pose_graph_calibration.h"
#include "slamkit/core/error.h"
#include "slamkit/core/output_file.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {

using io_detail::GraphBuilder;
using io_detail::TagFamily;

const char* to_string(PoseGraphFormat format) {
  switch (format) {
    case PoseGraphFormat::kAuto: return "auto";
    case PoseGraphFormat::kG2o: return "g2o";
    case PoseGraphFormat::kToro: return "toro";
    case PoseGraphFormat::kGtsam: return "gtsam";
  }
  return "?";
}

namespace {
std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}
}  // namespace

PoseGraphFormat parse_pose_graph_format(std::string_view name) {
  const std::string n = lower(name);
  for (PoseGraphFormat f : {PoseGraphFormat::kAuto, PoseGraphFormat::kG2o, PoseGraphFormat::kToro, PoseGraphFormat::kGtsam})
    if (n == to_string(f)) return f;
  throw InputError("", 0, "format", "unknown pose-graph format '" + std::string(name) + "' (use g2o, toro or gtsam)");
}

PoseGraphFormat format_from_extension(std::string_view path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext == ".g2o") return PoseGraphFormat::kG2o;
  if (ext == ".graph") return PoseGraphFormat::kToro;
  if (ext == ".txt") return PoseGraphFormat::kGtsam;
  return PoseGraphFormat::kAuto;
}

namespace {

const char* family_name(TagFamily f) {
  switch (f) {
    case TagFamily::kG2o: return "g2o";
    case TagFamily::kToro2d: return "TORO 2D";
    case TagFamily::kEdge3: return "TORO 3D / GTSAM";
    case TagFamily::kUnknown: break;
  }
  return "unknown";
}

// Whether records of family f may appear in a file of `format`.
bool accepts(PoseGraphFormat format, TagFamily f) {
  switch (format) {
    case PoseGraphFormat::kG2o: return f == TagFamily::kG2o;
    case PoseGraphFormat::kToro: return f == TagFamily::kToro2d || f == TagFamily::kEdge3;
    case PoseGraphFormat::kGtsam: return f == TagFamily::kEdge3;
    case PoseGraphFormat::kAuto: break;
  }
  return false;
}

// Gives every edges-only vertex an estimate; fails if the composition overflowed.
std::size_t complete_estimates(PoseGraph& g) {
  const std::size_t n = complete_estimates_by_odometry(g);
  for (const GraphVertex& v : g.vertices()) {
    const bool finite = v.pose2.translation().allFinite() && v.pose3.translation().allFinite() && v.point.allFinite();
    if (!finite) {
      throw InputError(g.source, 0, "",
                       "initial estimates composed from the odometry overflow (vertex " + std::to_string(v.id) + ")");
    }
  }
  return n;
}

// Every rotation the reader hands out (parsed, from roll/pitch/yaw, or composed by the
// odometry completion) is an exact-unit quaternion, a fixed point of g2o write → read.
void canonicalize_rotations(PoseGraph& g) {
  for (std::size_t i = 0; i < g.vertices().size(); ++i) {
    GraphVertex& v = g.vertex_at(i);
    if (v.kind == VertexKind::kPose3) v.pose3 = io_detail::exact_unit_rotation(v.pose3);
  }
  for (GraphEdge& e : g.edges)
    if (e.kind == EdgeKind::kPose3Pose3) e.pose3 = io_detail::exact_unit_rotation(e.pose3);
  for (auto& [id, offset] : g.sensor_offsets) offset = io_detail::exact_unit_rotation(offset);
}

PoseGraph read_records(TextReader& r, const PoseGraphReadOptions& options, PoseGraphReadReport& report) {
  report = PoseGraphReadReport{};
  PoseGraph g;
  g.source = r.source();
  GraphBuilder builder(g, report.warnings);
  const PoseGraphFormat hint = format_from_extension(r.source());
  PoseGraphFormat format = options.format;  // kAuto until the first known tag decides
  bool saw_toro2d = false;
  bool saw_record = false;
  while (r.next_line()) {
    saw_record = true;
    const std::string_view tag = r.field(0);
    const TagFamily family = io_detail::classify_tag(tag);
    if (format == PoseGraphFormat::kAuto && family != TagFamily::kUnknown)
      format = family == TagFamily::kG2o ? PoseGraphFormat::kG2o : PoseGraphFormat::kToro;  // TORO vs GTSAM: at the end
    if (format == PoseGraphFormat::kAuto || !accepts(format, family)) {
      std::string message = "unknown tag '" + std::string(tag.substr(0, 40)) + "'";
      if (family != TagFamily::kUnknown)
        message += " (a " + std::string(family_name(family)) + " tag, not part of the " + to_string(format) + " format)";
      if (!options.unknown_tags_as_warnings) r.fail("tag", message);
      builder.warn(r, message + ": line skipped");
      continue;
    }
    switch (family) {
      case TagFamily::kG2o: io_detail::read_g2o_record(r, builder); break;
      case TagFamily::kToro2d:
        saw_toro2d = true;
        io_detail::read_toro2d_record(r, builder);
        break;
      case TagFamily::kEdge3: io_detail::read_edge3_record(r, builder); break;
      case TagFamily::kUnknown: break;
    }
  }
  // EDGE3/VERTEX3-only text is TORO 3D or GTSAM: the same text. The extension decides.
  if (options.format == PoseGraphFormat::kAuto && format == PoseGraphFormat::kToro && !saw_toro2d &&
      hint != PoseGraphFormat::kToro)
    format = PoseGraphFormat::kGtsam;
  if (format == PoseGraphFormat::kAuto) format = hint == PoseGraphFormat::kAuto ? PoseGraphFormat::kG2o : hint;
  if (!saw_record) report.warnings.push_back(r.source() + ": the file holds no records (empty graph)");

  report.format = format;
  g.format = to_string(format);
  report.edges_only = builder.finish() && !g.edges.empty();
  if (report.edges_only && options.complete_estimates) report.completed_estimates = complete_estimates(g);
  canonicalize_rotations(g);
  report.information = check_information(g);
  if (options.repair_information) report.repaired_information = repair_information(g);
  return g;
}

}  // namespace

PoseGraph read_pose_graph(std::istream& in, const std::string& source, const PoseGraphReadOptions& options,
                          PoseGraphReadReport* report) {
  PoseGraphReadReport local;
  TextReader r(in, source);
  PoseGraph g = read_records(r, options, report ? *report : local);
  return g;
}

PoseGraph read_pose_graph(const std::string& path, const PoseGraphReadOptions& options, PoseGraphReadReport* report) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, 0, "", "is a directory, not a pose-graph file");
  const auto reader = TextReader::open(path);
  PoseGraphReadReport local;
  return read_records(*reader, options, report ? *report : local);
}

std::string pose_graph_to_string(const PoseGraph& g, PoseGraphFormat format, std::vector<std::string>* warnings) {
  if (format == PoseGraphFormat::kAuto)
    format = g.format.empty() ? PoseGraphFormat::kG2o : parse_pose_graph_format(g.format);
  if (format == PoseGraphFormat::kAuto) format = PoseGraphFormat::kG2o;
  io_detail::check_writable(g);
  if (format != PoseGraphFormat::kG2o && has_calibration(g) && warnings) {
    warnings->push_back(std::string(to_string(format)) +
                        " has no calibration tags: calibrated edges written with their effective measurements, "
                        "calibration vertices and parameters dropped");
  }
  std::string out;
  out.reserve(64 * (g.vertices().size() + 2 * g.edges.size()) + 256);
  switch (format) {
    case PoseGraphFormat::kG2o: io_detail::write_g2o(g, out, warnings); break;
    case PoseGraphFormat::kToro: io_detail::write_toro(g, out, warnings); break;
    case PoseGraphFormat::kGtsam: io_detail::write_gtsam(g, out, warnings); break;
    case PoseGraphFormat::kAuto: break;
  }
  return out;
}

void write_pose_graph(const PoseGraph& g, std::ostream& out, PoseGraphFormat format, std::vector<std::string>* warnings) {
  const std::string text = pose_graph_to_string(g, format, warnings);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw InputError("", 0, "", "error while writing the pose graph");
}

void write_pose_graph(const PoseGraph& g, const std::string& path, PoseGraphFormat format,
                      std::vector<std::string>* warnings) {
  if (format == PoseGraphFormat::kAuto) {
    format = format_from_extension(path);
    if (format == PoseGraphFormat::kAuto)
      throw InputError(path, 0, "", "cannot tell the output format from the extension (use .g2o, .graph or .txt, or name the format)");
  }
  // Format everything first: an impossible conversion must not leave a partial file behind.
  const std::string text = pose_graph_to_string(g, format, warnings);
  write_file_atomically(path, text);
}

}  // namespace slamkit
