// Every file of ../shared/datasets/posegraph: counts equal the README table, the initial chi2
// equals an independent computation (its own parser and plain Eigen), the same-format round
// trip is exact, and the README's caveats (cubicle's indefinite information, the
// odometry-initialized derived files) hold.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "graph_compare.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

struct DatasetRow {
  const char* file;
  const char* format;
  int dimension;
  int vertex_lines;  // the README's #vertices (0: edges only)
  int edges;
  int equivalences;
};

void PrintTo(const DatasetRow& row, std::ostream* os) { *os << row.file; }

// The README's file table.
const DatasetRow kDatasets[] = {
    {"2d/CSAIL.g2o", "g2o", 2, 0, 1171, 0},
    {"2d/city10000.g2o", "g2o", 2, 10000, 20687, 0},
    {"2d/derived/CSAIL_P_toro.g2o", "g2o", 2, 1045, 1172, 0},
    {"2d/derived/CSAIL_odominit.g2o", "g2o", 2, 1045, 1171, 0},
    {"2d/derived/manhattan_odominit.g2o", "g2o", 2, 3500, 5453, 0},
    {"2d/input_INTEL_g2o.g2o", "g2o", 2, 1228, 1483, 0},
    {"2d/input_M3500_g2o.g2o", "g2o", 2, 3500, 5453, 0},
    {"2d/input_M3500b_g2o.g2o", "g2o", 2, 3500, 5453, 0},
    {"2d/input_MITb_g2o.g2o", "g2o", 2, 808, 827, 0},
    {"2d/intel.g2o", "g2o", 2, 1728, 2512, 0},
    {"2d/manhattan.g2o", "g2o", 2, 0, 5453, 0},
    {"2d/toro/CSAIL_P_toro.graph", "toro", 2, 1045, 1172, 0},
    {"2d/toro/w100.graph", "toro", 2, 100, 300, 40},
    {"3d/cubicle.g2o", "g2o", 3, 5750, 16869, 0},
    {"3d/derived/cubicle_psd.g2o", "g2o", 3, 5750, 16869, 0},
    {"3d/gtsam_txt/sphere2500.txt", "gtsam", 3, 0, 4949, 0},
    {"3d/gtsam_txt/sphere2500_groundtruth.txt", "gtsam", 3, 0, 4949, 0},
    {"3d/parking-garage.g2o", "g2o", 3, 1661, 6275, 0},
    {"3d/sphere2500.g2o", "g2o", 3, 2500, 4949, 0},
    {"3d/tinyGrid3D.g2o", "g2o", 3, 9, 11, 0},
    {"3d/torus3D.g2o", "g2o", 3, 5000, 9048, 0},
};

// ---- an independent reference: istringstream parsing, Eigen isometries, g2o errors ----

using Matrix6 = Eigen::Matrix<double, 6, 6>;

struct Reference {
  std::map<long long, Eigen::Isometry2d> poses2;
  std::map<long long, Eigen::Isometry3d> poses3;
  struct Edge2 {
    long long i, j;
    Eigen::Isometry2d z;
    double dtheta;
    Eigen::Matrix3d info;  // in the file's own convention
    bool toro;
  };
  struct Edge3 {
    long long i, j;
    Eigen::Isometry3d z;
    Matrix6 info;  // in the file's own convention
    bool rotation_vector;
  };
  std::vector<Edge2> edges2;
  std::vector<Edge3> edges3;
  int vertex_lines = 0;
  int equivalences = 0;
};

template <int N>
Eigen::Matrix<double, N, N> upper(std::istringstream& in) {
  Eigen::Matrix<double, N, N> m;
  for (int r = 0; r < N; ++r)
    for (int c = r; c < N; ++c) {
      in >> m(r, c);
      m(c, r) = m(r, c);
    }
  return m;
}

Eigen::Isometry2d iso2(double x, double y, double th) { return Eigen::Translation2d(x, y) * Eigen::Rotation2Dd(th); }

Eigen::Isometry3d iso3(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  return Eigen::Translation3d(t) * q.normalized();
}

Eigen::Quaterniond rpy(double r, double p, double y) {
  return Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX());
}

Reference parse_reference(const std::string& path) {
  Reference g;
  std::ifstream file(path);
  std::string line, tag;
  while (std::getline(file, line)) {
    std::istringstream in(line);
    if (!(in >> tag)) continue;
    long long i, j;
    double x, y, z, a, b, c, d;
    if (tag == "VERTEX_SE2" || tag == "VERTEX2") {
      in >> i >> x >> y >> a;
      g.poses2[i] = iso2(x, y, a);
      ++g.vertex_lines;
    } else if (tag == "EDGE_SE2" || tag == "EDGE2") {
      in >> i >> j >> x >> y >> a;
      Eigen::Matrix3d info;
      if (tag == "EDGE_SE2") {
        info = upper<3>(in);
      } else {  // I11 I12 I22 I33 I13 I23
        double i11, i12, i22, i33, i13, i23;
        in >> i11 >> i12 >> i22 >> i33 >> i13 >> i23;
        info << i11, i12, i13, i12, i22, i23, i13, i23, i33;
      }
      g.edges2.push_back({i, j, iso2(x, y, a), a, info, tag == "EDGE2"});
    } else if (tag == "VERTEX_SE3:QUAT") {
      in >> i >> x >> y >> z >> a >> b >> c >> d;
      g.poses3[i] = iso3({x, y, z}, Eigen::Quaterniond(d, a, b, c));
      ++g.vertex_lines;
    } else if (tag == "EDGE_SE3:QUAT") {
      in >> i >> j >> x >> y >> z >> a >> b >> c >> d;
      g.edges3.push_back({i, j, iso3({x, y, z}, Eigen::Quaterniond(d, a, b, c)), upper<6>(in), false});
    } else if (tag == "EDGE3") {
      in >> i >> j >> x >> y >> z >> a >> b >> c;
      g.edges3.push_back({i, j, iso3({x, y, z}, rpy(a, b, c)), upper<6>(in), true});
    } else if (tag == "EQUIV") {
      ++g.equivalences;
    }
  }
  return g;
}

// Edges-only files: compose the odometry chain from the smallest id at the identity.
template <typename Pose, typename Edge>
void compose_chain(std::map<long long, Pose>& poses, const std::vector<Edge>& edges) {
  if (edges.empty()) return;
  std::map<std::pair<long long, long long>, Pose> step;
  std::set<long long> ids;
  for (const Edge& e : edges) {
    step[{e.i, e.j}] = e.z;
    step[{e.j, e.i}] = e.z.inverse();
    ids.insert(e.i);
    ids.insert(e.j);
  }
  long long prev = *ids.begin();
  poses[prev] = Pose::Identity();
  for (auto it = std::next(ids.begin()); it != ids.end(); ++it) {
    ASSERT_EQ(*it, prev + 1) << "ids are not contiguous";
    ASSERT_TRUE(step.count({prev, *it})) << "no odometry edge " << prev << "-" << *it;
    poses[*it] = poses[prev] * step[{prev, *it}];
    prev = *it;
  }
}

double reference_chi2(Reference& g) {
  if (g.vertex_lines == 0) {
    compose_chain(g.poses2, g.edges2);
    compose_chain(g.poses3, g.edges3);
  }
  double chi2 = 0.0;
  for (const auto& e : g.edges2) {
    const Eigen::Isometry2d E = e.z.inverse() * g.poses2.at(e.i).inverse() * g.poses2.at(e.j);
    Eigen::Vector3d r(E.translation().x(), E.translation().y(), std::atan2(E.linear()(1, 0), E.linear()(0, 0)));
    if (e.toro) r.head<2>() = Eigen::Rotation2Dd(e.dtheta) * r.head<2>();  // TORO's residual frame
    chi2 += r.dot(e.info * r);
  }
  for (const auto& e : g.edges3) {
    const Eigen::Isometry3d E = e.z.inverse() * g.poses3.at(e.i).inverse() * g.poses3.at(e.j);
    Eigen::Quaterniond q(E.linear());
    if (q.w() < 0.0) q.coeffs() *= -1.0;
    Eigen::Matrix<double, 6, 1> r;
    r << E.translation(), (e.rotation_vector ? 2.0 : 1.0) * q.vec();  // rotation vector ≈ 2 q.vec
    chi2 += r.dot(e.info * r);
  }
  return chi2;
}

TEST(PoseGraphDatasets, TableCoversEveryFile) {
  SLAMKIT_REQUIRE_DATA(root, "posegraph");
  std::set<std::string> listed;
  for (const DatasetRow& row : kDatasets) listed.insert(row.file);
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
    EXPECT_TRUE(listed.count(entry.path().lexically_relative(root).generic_string())) << entry.path();
  }
}

class PoseGraphDataset : public ::testing::TestWithParam<DatasetRow> {};

TEST_P(PoseGraphDataset, CountsAndInitialChi2MatchTheIndependentComputation) {
  const DatasetRow& row = GetParam();
  SLAMKIT_REQUIRE_DATA(path, std::string("posegraph/") + row.file);
  PoseGraphReadReport report;
  const PoseGraph g = read_pose_graph(path.string(), {}, &report);
  EXPECT_EQ(g.format, row.format);
  EXPECT_EQ(g.dimension(), row.dimension);
  EXPECT_EQ(g.edges.size(), static_cast<std::size_t>(row.edges));
  EXPECT_EQ(g.equivalences.size(), static_cast<std::size_t>(row.equivalences));
  EXPECT_EQ(report.edges_only, row.vertex_lines == 0);
  EXPECT_TRUE(report.warnings.empty());

  Reference ref = parse_reference(path.string());
  EXPECT_EQ(ref.vertex_lines, row.vertex_lines);
  EXPECT_EQ(ref.equivalences, row.equivalences);
  const double chi2 = reference_chi2(ref);
  const std::size_t ids = ref.poses2.size() + ref.poses3.size();
  EXPECT_EQ(g.vertices().size(), ids);
  if (row.vertex_lines > 0) {
    EXPECT_EQ(g.vertices().size(), static_cast<std::size_t>(row.vertex_lines));
  }
  EXPECT_NEAR(total_chi2(g) / chi2, 1.0, 1e-9) << total_chi2(g) << " vs " << chi2;
}

TEST_P(PoseGraphDataset, SameFormatRoundTrip) {
  const DatasetRow& row = GetParam();
  SLAMKIT_REQUIRE_DATA(path, std::string("posegraph/") + row.file);
  const PoseGraph a = read_pose_graph(path.string());
  const std::string text = pose_graph_to_string(a, PoseGraphFormat::kAuto);
  const PoseGraph b = testing::read_text(text, path.filename().string());
  if (a.format == "g2o") {
    EXPECT_TRUE(testing::same_graph(a, b, 0.0, 0.0));  // bit-identical
    EXPECT_EQ(pose_graph_to_string(b, PoseGraphFormat::kAuto), text);
  } else {
    // roll/pitch/yaw and TORO's rotated Ω pass through sin/cos: a few ulps.
    EXPECT_TRUE(testing::same_graph(a, b, 1e-14, 1e-14));
  }
}

INSTANTIATE_TEST_SUITE_P(AllFiles, PoseGraphDataset, ::testing::ValuesIn(kDatasets),
                         [](const ::testing::TestParamInfo<DatasetRow>& info) {
                           std::string name = info.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

TEST(PoseGraphDatasets, CubicleHas5021IndefiniteInformationMatrices) {
  SLAMKIT_REQUIRE_DATA(path, "posegraph/3d/cubicle.g2o");
  SLAMKIT_REQUIRE_DATA(psd_path, "posegraph/3d/derived/cubicle_psd.g2o");
  PoseGraphReadReport report;
  PoseGraph g = read_pose_graph(path.string(), {}, &report);
  EXPECT_EQ(report.information.indefinite, 5021u);
  EXPECT_EQ(report.information.singular, 0u);
  EXPECT_EQ(report.information.positive_definite, 16869u - 5021u);
  EXPECT_GT(report.information.first_bad_line, 5750);  // an edge line
  PoseGraphReadReport psd;
  read_pose_graph(psd_path.string(), {}, &psd);
  EXPECT_EQ(psd.information.bad(), 0u);
  PoseGraphReadOptions repair;
  repair.repair_information = true;
  PoseGraphReadReport repaired;
  g = read_pose_graph(path.string(), repair, &repaired);
  EXPECT_EQ(repaired.repaired_information, 5021u);
  EXPECT_EQ(check_information(g).bad(), 0u);
}

double round9(double v) {  // the derived files print %.9g
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return std::strtod(buf, nullptr);
}

// The derived *_odominit.g2o files were made by the same odometry composition, printed with 9
// significant digits. Our completion agrees to those digits, and rounded to them it gives a
// bit-identical initial chi2.
TEST(PoseGraphDatasets, EdgesOnlyCompletionReproducesTheDerivedFiles) {
  for (const auto& [edges_only, derived] : {std::pair{"2d/manhattan.g2o", "2d/derived/manhattan_odominit.g2o"},
                                             std::pair{"2d/CSAIL.g2o", "2d/derived/CSAIL_odominit.g2o"}}) {
    SLAMKIT_REQUIRE_DATA(a_path, std::string("posegraph/") + edges_only);
    SLAMKIT_REQUIRE_DATA(b_path, std::string("posegraph/") + derived);
    PoseGraph a = read_pose_graph(a_path.string());
    const PoseGraph b = read_pose_graph(b_path.string());
    ASSERT_EQ(a.vertices().size(), b.vertices().size());
    EXPECT_NEAR(total_chi2(a) / total_chi2(b), 1.0, 1e-7) << edges_only;
    for (std::size_t i = 0; i < a.vertices().size(); ++i) {
      GraphVertex& v = a.vertex_at(i);
      const SE2& w = b.vertex(v.id).pose2;
      for (const auto& [x, y] : {std::pair{v.pose2.x(), w.x()}, {v.pose2.y(), w.y()}, {v.pose2.theta(), w.theta()}})
        ASSERT_LE(std::abs(x - y), 5e-9 * std::abs(y) + 1e-300) << edges_only << " vertex " << v.id;
      v.pose2 = SE2(round9(v.pose2.x()), round9(v.pose2.y()), round9(v.pose2.theta()));
    }
    EXPECT_EQ(total_chi2(a), total_chi2(b)) << edges_only;
  }
}

}  // namespace
}  // namespace slamkit
