// Internal to src/io: the pieces the pose-graph format files share.
//
// GraphBuilder collects the records of one file and runs the checks that need the whole
// file (edge endpoints, vertex kinds, FIX/EQUIV references, edges-only vertices). The
// field readers parse and validate one group of fields and fail at the reader's line
// naming the field. The per-format functions read one record or write a whole graph.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "slamkit/core/pose_graph.h"
#include "slamkit/io/text_reader.h"

namespace slamkit::io_detail {

class GraphBuilder {
 public:
  GraphBuilder(PoseGraph& graph, std::vector<std::string>& warnings) : g_(graph), warnings_(warnings) {}

  /// Fails at the current line if the file already holds records of the other dimension.
  void require_dimension(const TextReader& r, int dimension);
  /// Fails on a duplicate id (field `id`).
  void add_vertex(const TextReader& r, GraphVertex v);
  /// Fails on a self-loop (field `to`); endpoints are resolved in finish().
  void add_edge(const TextReader& r, GraphEdge e);
  void add_fixed(const TextReader& r, std::int64_t id);
  void add_equivalence(const TextReader& r, std::int64_t a, std::int64_t b);
  /// Fails on a duplicate parameter id.
  void add_sensor_offset(const TextReader& r, int id, const SE3& offset);
  /// Calibration records (core/calibration.h). Fails on duplicate ids.
  void add_offset_parameter2(const TextReader& r, int id, const SE2& offset);
  void add_calibration_vertex(const TextReader& r, CalibrationVertex v);
  void add_calibration_prior(const TextReader& r, CalibrationPrior p);
  void warn(const TextReader& r, const std::string& message);

  /// Resolves every reference; in an edges-only file first creates the vertices the edges
  /// name (has_estimate = false). Returns true for an edges-only file.
  bool finish();

 private:
  struct Reference {
    std::int64_t id;
    int line;
    const char* field;
    const char* tag;
  };
  void check_reference(const Reference& ref) const;
  void create_vertices_from_edges();
  void check_edge_kinds() const;
  /// VERTEX_SE2 lines named as offsets by EDGE_SE2_CALIB become calibration vertices; FIX of a
  /// calibration vertex holds it; every calibrated edge's parameters must exist.
  void resolve_calibration();

  PoseGraph& g_;
  std::vector<std::string>& warnings_;
  int dimension_ = 0;
  int dimension_line_ = 0;
  bool has_vertex_lines_ = false;
  std::vector<Reference> references_;  // FIX and EQUIV ids
};

// ---- field readers (fail naming the field) ----

/// Name of the information entry (row, col), 0-based: "I11", "I12", ...
const char* information_field_name(int row, int col);
/// Fails unless the line has exactly 1 + head.size() + n(n+1)/2 fields (tag, `head`, the upper
/// triangle of an n×n information). A short line names its first missing field, a long one "extra".
void expect_record(const TextReader& r, std::initializer_list<const char*> head, int info_dim);

/// A vertex id: an integer in [0, 2⁶³ − 2] (so that id + 1 and id differences never overflow).
std::int64_t read_id(const TextReader& r, std::size_t i, std::string_view name);
/// q/‖q‖, then nudged by single ulps until Eigen's norm() of it is exactly 1.0, so that
/// normalizing it again (as SO3 does) changes no bit: the fixed point that makes g2o
/// write → read bit-identical. q must be non-zero and finite.
Eigen::Quaterniond exact_unit_quaternion(const Eigen::Quaterniond& q);
/// T with its rotation replaced by exact_unit_quaternion of it.
SE3 exact_unit_rotation(const SE3& T);
/// Fields i..i+3 = qx qy qz qw as exact_unit_quaternion. Fails on a zero quaternion or one of
/// norm < 1e-6.
Eigen::Quaterniond read_quaternion(const TextReader& r, std::size_t i);
/// Fields i.. hold the upper triangle of an n×n matrix row by row (g2o order); names "I11"...
Eigen::MatrixXd read_upper_triangle(const TextReader& r, std::size_t i, int n);
/// Fails (field "information") unless every entry of omega is finite, e.g. after a conversion.
void require_finite_information(const TextReader& r, const Eigen::MatrixXd& omega);

// ---- writers' number formatting: shortest representation that reads back bit-identical ----

void append_number(std::string& out, double v);
void append_integer(std::string& out, std::int64_t v);
/// Appends ' ' + v for each value.
void append_numbers(std::string& out, std::initializer_list<double> values);
/// Appends the upper triangle of omega row by row, each preceded by ' '.
void append_upper_triangle(std::string& out, const Eigen::MatrixXd& omega);
/// Everything a writer relies on, for graphs built in memory: finite numbers, information of
/// the right size, ids in range, edges between existing vertices of the right kinds, known
/// sensor offsets, FIX/EQUIV of existing vertices. Throws InputError naming the element.
void check_writable(const PoseGraph& g);
/// Fails unless all vertices have an estimate or none has (then returns false: write edges only).
bool vertices_to_write(const PoseGraph& g, const char* format);

// ---- formats ----

enum class TagFamily { kUnknown, kG2o, kToro2d, kEdge3 };
TagFamily classify_tag(std::string_view tag);

void read_g2o_record(const TextReader& r, GraphBuilder& b);
/// The calibration tags (g2o_calibration_format.cpp); false if `tag` is not one of them.
bool read_g2o_calibration_record(const TextReader& r, GraphBuilder& b);
/// Lines of the calibration section: PARAMS_SE2OFFSET, calibration vertices, their FIX, priors.
void write_g2o_calibration_section(const PoseGraph& g, std::string& out);
/// The line of a calibrated edge.
void append_g2o_calibrated_edge(std::string& out, const GraphEdge& e);
/// Whether `tag` is one of the calibration tags.
bool is_g2o_calibration_tag(std::string_view tag);
/// TORO VERTEX2 / EDGE2 / EQUIV.
void read_toro2d_record(const TextReader& r, GraphBuilder& b);
/// VERTEX3 / EDGE3 (TORO 3D and GTSAM: the same text).
void read_edge3_record(const TextReader& r, GraphBuilder& b);

void write_g2o(const PoseGraph& g, std::string& out, std::vector<std::string>* warnings);
void write_toro(const PoseGraph& g, std::string& out, std::vector<std::string>* warnings);
void write_gtsam(const PoseGraph& g, std::string& out, std::vector<std::string>* warnings);
/// VERTEX3 / EDGE3 lines for a 3D pose graph (shared by the TORO 3D and GTSAM writers);
/// `format` names the target in error messages.
void write_edge3_records(const PoseGraph& g, std::string& out, const char* format);

}  // namespace slamkit::io_detail
