// read_pose_graph / write_pose_graph: strictness (file, line, field of every error kind),
// format detection, unknown-tag warnings, edges-only completion, information health, and
// the conversions a format cannot represent.
#include "slamkit/io/pose_graph_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "graph_compare.h"
#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"

namespace slamkit {
namespace {

using testing::read_text;

struct BadInput {
  const char* what;
  const char* source;  // name (its extension is the format hint)
  const char* text;
  int line;
  const char* field;
  const char* message;  // substring of what()
};

const char* const kV2 = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";

std::string with_v2(const char* tail) { return std::string(kV2) + tail; }

TEST(PoseGraphIo, EveryErrorNamesFileLineAndField) {
  const std::string e_ok = "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n";
  const BadInput cases[] = {
      {"malformed number", "a.g2o", "VERTEX_SE2 0 1.0abc 0 0\n", 1, "x", "not a number"},
      {"too few fields", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0\n", 3, "I33",
       "missing"},
      {"too many fields", "a.g2o", "VERTEX_SE2 0 0 0 0 7\n", 1, "extra", "needs 5 fields"},
      {"missing head field", "a.g2o", "VERTEX_SE3:QUAT 0 1 2\n", 1, "z", "missing"},
      {"NaN", "a.g2o", "VERTEX_SE2 0 nan 0 0\n", 1, "x", "not finite"},
      {"Inf in information", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 inf 0 1\n", 3,
       "I22", "not finite"},
      {"non-integer id", "a.g2o", "VERTEX_SE2 1.5 0 0 0\n", 1, "id", "not an integer"},
      {"negative id", "a.g2o", "VERTEX_SE2 -3 0 0 0\n", 1, "id", "vertex id must be"},
      {"id overflow", "a.g2o", "VERTEX_SE2 99999999999999999999 0 0 0\n", 1, "id", "out of range"},
      {"duplicate vertex", "a.g2o", "VERTEX_SE2 0 0 0 0\n# c\nVERTEX_SE2 0 1 1 1\n", 3, "id", "first defined on line 1"},
      {"edge to unknown vertex", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nEDGE_SE2 0 5 1 0 0 1 0 0 1 0 1\n", 3,
       "to", "unknown vertex 5"},
      {"edge from unknown vertex", "a.g2o", "VERTEX_SE2 0 0 0 0\nEDGE_SE2 9 0 1 0 0 1 0 0 1 0 1\nVERTEX_SE2 1 0 0 0\n", 2,
       "from", "unknown vertex 9"},
      {"self loop", "a.g2o", "VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 0 1 0 0 1 0 0 1 0 1\n", 2, "to", "itself"},
      {"zero quaternion", "a.g2o", "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 0\n", 1, "quaternion", "zero quaternion"},
      {"tiny quaternion", "a.g2o", "VERTEX_SE3:QUAT 0 0 0 0 1e-300 0 0 1e-300\n", 1, "quaternion", "too small"},
      {"unknown tag", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_CAM 1 2 3\n", 2, "tag", "unknown tag 'VERTEX_CAM'"},
      {"other format's tag", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX2 1 0 0 0\n", 2, "tag", "TORO 2D tag"},
      {"mixed 2D and 3D", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n", 2, "tag", "3D record in a 2D"},
      {"edge kind vs vertex kind", "a.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_XY 1 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n", 3,
       "to", "is point2 (line 2)"},
      {"unknown sensor offset", "a.g2o",
       "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_TRACKXYZ 1 0 0 0\nEDGE_SE3_TRACKXYZ 0 1 4 1 1 1 1 0 0 1 0 1\n", 3,
       "param_id", "PARAMS_SE3OFFSET"},
      {"duplicate sensor offset", "a.g2o", "PARAMS_SE3OFFSET 1 0 0 0 0 0 0 1\nPARAMS_SE3OFFSET 1 0 0 0 0 0 0 1\n", 2, "id",
       "duplicate parameter"},
      {"FIX without id", "a.g2o", "VERTEX_SE2 0 0 0 0\nFIX\n", 2, "id", "at least one"},
      {"edges-only kind clash", "a.g2o", "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2_XY 0 1 1 1 1 0 1\n", 2, "to",
       "is pose2"},
      {"TORO info order count", "a.graph", "VERTEX2 0 0 0 0\nVERTEX2 1 0 0 0\nEDGE2 0 1 1 0 0 1 0 1 1 0\n", 3, "I23",
       "missing"},
      {"EQUIV unknown vertex", "a.graph", "VERTEX2 0 0 0 0\nEQUIV 0 8\n", 2, "b", "EQUIV names unknown vertex 8"},
      {"EQUIV with itself", "a.graph", "VERTEX2 0 0 0 0\nEQUIV 0 0\n", 2, "b", "itself"},
      {"EDGE3 overflowing information", "a.txt",
       "EDGE3 0 1 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1e308 0 0 1 0 1\n", 1, "information", "overflows"},
      {"EDGE3 bad angle", "a.txt", "EDGE3 0 1 0 0 0 0 x 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n", 1, "pitch",
       "not a number"},
  };
  for (const BadInput& c : cases) {
    SCOPED_TRACE(c.what);
    try {
      read_text(c.text, c.source);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), c.source);
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
      const std::string prefix = std::string(c.source) + ":" + std::to_string(c.line) + ": field '" + c.field + "'";
      EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
    }
  }
}

TEST(PoseGraphIo, ForcedFormatRejectsOtherTags) {
  PoseGraphReadOptions o;
  o.format = PoseGraphFormat::kGtsam;
  try {
    read_text("EDGE2 0 1 1 0 0 1 0 1 1 0 0\n", "w.graph", o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.field(), "tag");
    EXPECT_NE(std::string(e.what()).find("not part of the gtsam format"), std::string::npos) << e.what();
  }
  o.format = PoseGraphFormat::kToro;
  PoseGraphReadReport r;
  read_text("EDGE3 0 1 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n", "x.txt", o, &r);
  EXPECT_EQ(r.format, PoseGraphFormat::kToro);
}

TEST(PoseGraphIo, DetectsFormatByFirstTagWithExtensionHint) {
  const std::string edge3 = "EDGE3 0 1 0 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n";
  const struct {
    std::string text, name;
    PoseGraphFormat want;
  } cases[] = {
      {with_v2(""), "graph.dat", PoseGraphFormat::kG2o},
      {"VERTEX2 0 0 0 0\n", "graph.g2o", PoseGraphFormat::kToro},  // tags win over the extension
      {edge3, "sphere.txt", PoseGraphFormat::kGtsam},
      {edge3, "sphere.graph", PoseGraphFormat::kToro},
      {edge3, "sphere", PoseGraphFormat::kGtsam},
      {"# only a comment\n", "empty.graph", PoseGraphFormat::kToro},
      {"", "empty", PoseGraphFormat::kG2o},
  };
  for (const auto& c : cases) {
    PoseGraphReadReport r;
    const PoseGraph g = read_text(c.text, c.name, {}, &r);
    EXPECT_EQ(r.format, c.want) << c.name;
    EXPECT_EQ(g.format, to_string(c.want));
  }
  EXPECT_EQ(parse_pose_graph_format("GTSAM"), PoseGraphFormat::kGtsam);
  EXPECT_THROW(parse_pose_graph_format("bal"), InputError);
  EXPECT_EQ(format_from_extension("/a/b.G2O"), PoseGraphFormat::kG2o);
}

TEST(PoseGraphIo, UnknownTagsCanBeWarnings) {
  PoseGraphReadOptions o;
  o.unknown_tags_as_warnings = true;
  PoseGraphReadReport r;
  const PoseGraph g = read_text("VERTEX_CAM 9 1\n" + with_v2("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nVERTEX2 5 0 0 0\n"), "w.g2o",
                                o, &r);
  EXPECT_EQ(g.vertices().size(), 2u);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_EQ(r.warnings[0].rfind("w.g2o:1: unknown tag 'VERTEX_CAM'", 0), 0u) << r.warnings[0];
  EXPECT_EQ(r.warnings[1].rfind("w.g2o:5: unknown tag 'VERTEX2'", 0), 0u) << r.warnings[1];
  // Other errors stay errors.
  EXPECT_THROW(read_text("VERTEX_CAM 9 1\nVERTEX_SE2 0 x 0 0\n", "w.g2o", o), InputError);
}

TEST(PoseGraphIo, MissingFileAndDirectoryAreClearErrors) {
  try {
    read_pose_graph("/nonexistent/graph.g2o");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/graph.g2o");
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_pose_graph(std::filesystem::temp_directory_path().string()), InputError);
}

TEST(PoseGraphIo, EdgesOnlyFilesGetVerticesFromTheOdometry) {
  PoseGraphReadReport r;
  const PoseGraph g = read_text(
      "EDGE_SE2 10 11 1 0 1.5707963267948966 1 0 0 1 0 1\nEDGE_SE2 11 12 1 0 0 1 0 0 1 0 1\n"
      "EDGE_SE2_XY 12 20 2 0 1 0 1\n",
      "e.g2o", {}, &r);
  EXPECT_TRUE(r.edges_only);
  EXPECT_EQ(r.completed_estimates, 4u);
  ASSERT_EQ(g.vertices().size(), 4u);
  EXPECT_EQ(g.vertices()[0].id, 10);  // created in id order
  EXPECT_EQ(g.vertex(20).kind, VertexKind::kPoint2);
  EXPECT_NEAR(g.vertex(12).pose2.x(), 1.0, 1e-15);
  EXPECT_NEAR(g.vertex(12).pose2.y(), 1.0, 1e-15);
  EXPECT_NEAR(g.vertex(20).point.y(), 3.0, 1e-15);
  EXPECT_NEAR(total_chi2(g), 0.0, 1e-24);
}

TEST(PoseGraphIo, RecordsInformationHealthAndRepairsOnRequest) {
  // One PD, one singular, one indefinite information matrix.
  const std::string text = with_v2(
      "VERTEX_SE2 2 2 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
      "EDGE_SE2 1 2 1 0 0 1 0 0 0 0 1\nEDGE_SE2 0 2 2 0 0 1 2 0 1 0 1\n");
  PoseGraphReadReport r;
  const PoseGraph g = read_text(text, "h.g2o", {}, &r);
  EXPECT_EQ(r.information.positive_definite, 1u);
  EXPECT_EQ(r.information.singular, 1u);
  EXPECT_EQ(r.information.indefinite, 1u);
  EXPECT_EQ(r.information.first_bad_line, 5);
  EXPECT_EQ(r.repaired_information, 0u);
  EXPECT_EQ(check_information(g.edges[2].information).status, InformationStatus::kIndefinite);

  PoseGraphReadOptions o;
  o.repair_information = true;
  PoseGraphReadReport repaired;
  const PoseGraph h = read_text(text, "h.g2o", o, &repaired);
  EXPECT_EQ(repaired.information.indefinite, 1u);  // health as read
  EXPECT_EQ(repaired.repaired_information, 2u);
  EXPECT_EQ(check_information(h).bad(), 0u);
  // Repaired matrices stay exactly symmetric, so they survive a write → read (found by fuzzing).
  for (const GraphEdge& e : h.edges) EXPECT_EQ(e.information, e.information.transpose());
  EXPECT_TRUE(testing::same_graph(h, read_text(pose_graph_to_string(h, PoseGraphFormat::kG2o)), 0.0, 0.0));
}

TEST(PoseGraphIo, ImpossibleConversionsFailBeforeWriting) {
  const PoseGraph landmarks = read_text("VERTEX_SE2 0 0 0 0\nVERTEX_XY 1 1 1\nEDGE_SE2_XY 0 1 1 1 1 0 1\n");
  const auto dir = std::filesystem::temp_directory_path() / "slamkit_io_test";
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "landmarks.graph").string();
  std::filesystem::remove(out);
  try {
    write_pose_graph(landmarks, out);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("TORO has no tag for point2 vertices"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 2);
  }
  EXPECT_FALSE(std::filesystem::exists(out));  // nothing half-written

  const PoseGraph planar = read_text(with_v2("EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"));
  EXPECT_THROW(pose_graph_to_string(planar, PoseGraphFormat::kGtsam), InputError);
  EXPECT_THROW(write_pose_graph(planar, (dir / "x.unknown").string()), InputError);  // no format
  EXPECT_THROW(write_pose_graph(planar, "/nonexistent/dir/x.g2o"), InputError);

  PoseGraph broken = planar;
  broken.edges[0].information = Eigen::Matrix2d::Identity();
  EXPECT_THROW(pose_graph_to_string(broken, PoseGraphFormat::kG2o), InputError);
  broken = planar;
  broken.vertex_at(1).pose2 = SE2(std::nan(""), 0.0, 0.0);
  EXPECT_THROW(pose_graph_to_string(broken, PoseGraphFormat::kG2o), InputError);
  // Graphs built in memory are checked too: the written file must be readable.
  broken = planar;
  broken.edges[0].to = 9;
  EXPECT_THROW(pose_graph_to_string(broken, PoseGraphFormat::kG2o), InputError);
  broken = planar;
  broken.fixed.push_back(7);
  EXPECT_THROW(pose_graph_to_string(broken, PoseGraphFormat::kG2o), InputError);
  broken = planar;
  broken.edges[0].kind = EdgeKind::kPose2Point2;
  broken.edges[0].information = Eigen::Matrix2d::Identity();
  EXPECT_THROW(pose_graph_to_string(broken, PoseGraphFormat::kG2o), InputError);
}

TEST(PoseGraphIo, DroppedElementsAreReportedAsWarnings) {
  const PoseGraph w = read_text("VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nEDGE2 0 1 1 0 0 1 0 1 1 0 0\nEQUIV 0 1\n", "w.graph");
  std::vector<std::string> warnings;
  const std::string g2o = pose_graph_to_string(w, PoseGraphFormat::kG2o, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("1 vertex equivalences dropped"), std::string::npos);
  EXPECT_EQ(g2o.find("EQUIV"), std::string::npos);

  const PoseGraph fixed = read_text(with_v2("FIX 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"));
  warnings.clear();
  pose_graph_to_string(fixed, PoseGraphFormat::kToro, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no FIX tag"), std::string::npos);
}

TEST(PoseGraphIo, FileAndStreamVariantsAgree) {
  const std::string text = with_v2("EDGE_SE2 0 1 1 0 0.25 1 0 0 1 0 1\n");
  const auto dir = std::filesystem::temp_directory_path() / "slamkit_io_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "two.g2o").string();
  {
    std::ofstream f(path);
    f << text;
  }
  const PoseGraph a = read_pose_graph(path);
  EXPECT_EQ(a.source, path);
  write_pose_graph(a, (dir / "two_out.g2o").string());
  EXPECT_TRUE(testing::same_graph(a, read_pose_graph((dir / "two_out.g2o").string()), 0.0, 0.0));
  EXPECT_TRUE(testing::same_graph(a, read_text(text), 0.0, 0.0));
}

}  // namespace
}  // namespace slamkit
