// BAL reader/writer: strict parsing with file:line:field errors, bit-identical round trip,
// normalization that keeps the cost, seeded perturbation, geometry checks, real files.
#include <gtest/gtest.h>

#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/io/bal_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

const char* kSmall =
    "2 3 5\n"
    "0 0 -10.5 3.25\n"
    "1 0 -12 4\n"
    "0 1 8 -1\n"
    "1 2 1e1 2.5\n"
    "0 2 0.5 0.25\n"
    "0.01\n0.02\n-0.03\n0.1\n-0.2\n-5\n500\n1e-3\n-1e-5\n"
    "0.02 -0.01 0.0 0.3 0.1 -6 510 0 0\n"  // several values per line are fine
    "\n"
    "0.5\n0.5\n1\n-0.5\n0.25\n0.5\n0\n0\n0.5\n";

BalProblem parse(const std::string& text) {
  std::istringstream in(text);
  return read_bal(in, "t.bal");
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(BalIo, ReadsTheSmallProblem) {
  const BalProblem p = parse(kSmall);
  ASSERT_EQ(p.num_cameras(), 2);
  ASSERT_EQ(p.num_points(), 3);
  ASSERT_EQ(p.num_observations(), 5);
  EXPECT_EQ(p.observations[3].camera, 1);
  EXPECT_EQ(p.observations[3].point, 2);
  EXPECT_EQ(p.observations[3].pixel.x(), 10.0);
  EXPECT_EQ(p.cameras[0][6], 500.0);
  EXPECT_EQ(p.cameras[1][5], -6.0);
  EXPECT_EQ(p.points[2].z(), 0.5);
}

TEST(BalIo, RoundTripIsBitIdentical) {
  BalProblem p = parse(kSmall);
  p.points[1].x() = 0.1 + 0.2;  // needs 17 digits
  const BalProblem q = parse(bal_to_string(p));
  EXPECT_EQ(bal_to_string(p), bal_to_string(q));
  for (int j = 0; j < p.num_points(); ++j) EXPECT_EQ(p.points[j], q.points[j]);
}

TEST(BalIo, ErrorsNameFileLineAndField) {
  EXPECT_EQ(error_of("2 3\n"), "t.bal:1: field 'num_observations': the file ends early (truncated?)");
  EXPECT_NE(error_of("0 3 5\n").find("field 'num_cameras': must be a positive count"), std::string::npos);
  EXPECT_NE(error_of("2 3 1\n2 0 1 1\n").find("t.bal:2: field 'observation 0 camera': camera index 2 out of range"),
            std::string::npos);
  EXPECT_NE(error_of("2 3 1\n0 -1 1 1\n").find("t.bal:2: field 'observation 0 point': point index -1"), std::string::npos);
  std::string nan = kSmall;
  nan.replace(nan.find("500"), 3, "nan");
  EXPECT_NE(error_of(nan).find("t.bal:13: field 'camera 0 f'"), std::string::npos) << error_of(nan);
  std::string truncated(kSmall);
  truncated.resize(truncated.size() - 6);
  EXPECT_NE(error_of(truncated).find("field 'point 2 y': the file ends early"), std::string::npos) << error_of(truncated);
  EXPECT_NE(error_of(std::string(kSmall) + "7\n").find("unexpected data after the last point"), std::string::npos);
  EXPECT_NE(error_of("2 3 1\n0 1.5 1 1\n").find("field 'observation 0 point'"), std::string::npos);
  EXPECT_NE(error_of("2 3 5\n0 0 1e400 1\n").find("field 'observation 0 x'"), std::string::npos);
}

TEST(BalIo, NormalizationKeepsTheCostAndScalesTheScene) {
  BalProblem p = parse(kSmall);
  const double cost = bal_cost(p);
  const double s = normalize_bal(p);
  EXPECT_GT(s, 0.0);
  EXPECT_NEAR(bal_cost(p), cost, 1e-9 * cost);
  std::vector<double> dev;
  for (const auto& X : p.points) dev.push_back(X.lpNorm<1>());
  std::sort(dev.begin(), dev.end());
  EXPECT_NEAR(dev[dev.size() / 2], 100.0, 1e-9);
}

TEST(BalIo, PerturbationIsSeeded) {
  BalProblem a = parse(kSmall), b = parse(kSmall), c = parse(kSmall);
  perturb_bal(a, {0.01, 0.1, 0.1, 7});
  perturb_bal(b, {0.01, 0.1, 0.1, 7});
  perturb_bal(c, {0.01, 0.1, 0.1, 8});
  EXPECT_EQ(bal_to_string(a), bal_to_string(b));
  EXPECT_NE(bal_to_string(a), bal_to_string(c));
  EXPECT_NE(bal_to_string(a), bal_to_string(parse(kSmall)));
}

TEST(BalIo, GeometryChecks) {
  BalProblem p = parse(kSmall);
  BalReadReport report;
  validate_bal_geometry(p, &report);  // finite: passes (points behind cameras are warnings)
  // A point exactly on a camera's plane makes the prediction infinite: rejected with its line.
  p.points[0] = Eigen::Vector3d::Zero();
  p.cameras[0].setZero();
  p.cameras[0][6] = 500;
  try {
    validate_bal_geometry(p);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 2);
  }
}

TEST(BalIo, PointBehindEveryCameraIsReported) {
  BalProblem p = parse(kSmall);
  // Put point 1 behind camera 0 (its only observer): P.z > 0.
  p.cameras[0].setZero();
  p.cameras[0][6] = 500;
  p.points[1] = Eigen::Vector3d(0.1, 0.1, 5.0);
  BalReadReport report;
  validate_bal_geometry(p, &report);
  bool found = false;
  for (const auto& w : report.warnings) found = found || w.find("behind every camera") != std::string::npos;
  EXPECT_TRUE(found);
}

TEST(BalIo, RealProblemsLoad) {
  SLAMKIT_REQUIRE_DATA(dir, "bal");
  const BalProblem p = read_bal((dir / "problem-49-7776-pre.txt").string());
  EXPECT_EQ(p.num_cameras(), 49);
  EXPECT_EQ(p.num_points(), 7776);
  EXPECT_EQ(p.num_observations(), 31843);
  EXPECT_NEAR(bal_cost(p), 8.509e5, 0.001e5);  // Ceres' initial cost
  const BalProblem q = read_bal((dir / "problem-21-11315-pre.txt").string());
  EXPECT_EQ(q.num_observations(), 36455);
  EXPECT_NEAR(bal_cost(q), 4.413e6, 0.001e6);
  BalProblem n = q;
  const double s = normalize_bal(n);
  EXPECT_NEAR(s, 61.23, 0.01);  // the README's figure
  EXPECT_NEAR(bal_cost(n), bal_cost(q), 1e-8 * bal_cost(q));
  EXPECT_TRUE(looks_like_bal_path((dir / "problem-21-11315-pre.txt").string()));
  EXPECT_FALSE(looks_like_bal_path("sphere2500.g2o"));
}

}  // namespace
}  // namespace slamkit
