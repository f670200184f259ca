// Reading and writing pose-graph files: g2o, TORO (2D and 3D) and GTSAM EDGE3 text.
//
// Every reader is strict (docs/formats.md): a malformed line, a wrong field count, a
// non-finite number, a non-integer or duplicate id, an edge to an unknown vertex (when
// the file has vertex lines), a zero quaternion or an unknown tag throws InputError
// naming the file, the line and the field. Unknown tags may be downgraded to warnings.
//
// The PoseGraph always holds information matrices in g2o's error coordinates
// (pose_graph.h); readers and writers of the other formats convert
// (information_conventions.h). Format detection: the first recognised tag decides the
// family (g2o tags vs TORO/GTSAM tags); TORO 3D and GTSAM EDGE3 are the same text, told
// apart by the extension (".graph" = TORO, anything else = GTSAM) unless forced.
//
// Edges-only files (no vertex line at all, e.g. SE-Sync's manhattan.g2o) get one vertex
// per id named by the edges, with has_estimate = false, then (by default)
// complete_estimates_by_odometry().
//
// Writers use the shortest round-trip representation of every double, so g2o
// read → write → read is bit-identical. TORO/GTSAM round trips are exact for
// translations, 2D angles and 3D information; rotations given as roll/pitch/yaw and the
// rotated TORO 2D information agree to a few ulps (their conversion involves sin/cos).
// All functions are reentrant; no global state.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include "slamkit/core/information.h"
#include "slamkit/core/pose_graph.h"

namespace slamkit {

enum class PoseGraphFormat { kAuto, kG2o, kToro, kGtsam };

/// "auto", "g2o", "toro", "gtsam".
const char* to_string(PoseGraphFormat format);
/// Inverse of to_string (case-insensitive); throws InputError("", 0, "format", ...) otherwise.
PoseGraphFormat parse_pose_graph_format(std::string_view name);
/// ".g2o" → g2o, ".graph" → TORO, ".txt" → GTSAM, anything else → kAuto.
PoseGraphFormat format_from_extension(std::string_view path);

struct PoseGraphReadOptions {
  PoseGraphFormat format = PoseGraphFormat::kAuto;  ///< force a format instead of detecting it
  bool unknown_tags_as_warnings = false;  ///< skip unknown tags with a warning instead of failing
  bool repair_information = false;        ///< project non-PD information matrices to the PSD cone
  bool complete_estimates = true;         ///< edges-only files: initialize by odometry composition
};

/// What the reader found besides the graph itself.
struct PoseGraphReadReport {
  PoseGraphFormat format = PoseGraphFormat::kAuto;  ///< the format that was read
  std::vector<std::string> warnings;                 ///< "FILE:LINE: message", in file order
  InformationHealth information;       ///< health of the information matrices as read
  std::size_t repaired_information = 0;  ///< matrices changed by repair_information
  bool edges_only = false;               ///< the file had no vertex line
  std::size_t completed_estimates = 0;   ///< vertices initialized by odometry composition
};

/// Reads a pose-graph file. Throws InputError on any problem, including a missing file.
PoseGraph read_pose_graph(const std::string& path, const PoseGraphReadOptions& options = {},
                          PoseGraphReadReport* report = nullptr);
/// Reads from a stream; `source` names it in messages and its extension is the format hint.
PoseGraph read_pose_graph(std::istream& in, const std::string& source,
                          const PoseGraphReadOptions& options = {}, PoseGraphReadReport* report = nullptr);

/// Writes g in `format` (kAuto: from the path's extension). Throws InputError when the
/// format cannot represent the graph (e.g. landmarks in TORO, 2D in GTSAM) before writing
/// anything. Elements the format has no tag for (EQUIV in g2o/GTSAM, FIX in TORO/GTSAM)
/// are dropped with a warning appended to `warnings`.
void write_pose_graph(const PoseGraph& g, const std::string& path, PoseGraphFormat format = PoseGraphFormat::kAuto,
                      std::vector<std::string>* warnings = nullptr);
/// Stream variant; kAuto uses g.format.
void write_pose_graph(const PoseGraph& g, std::ostream& out, PoseGraphFormat format,
                      std::vector<std::string>* warnings = nullptr);
/// The text write_pose_graph would produce.
std::string pose_graph_to_string(const PoseGraph& g, PoseGraphFormat format,
                                 std::vector<std::string>* warnings = nullptr);

}  // namespace slamkit
