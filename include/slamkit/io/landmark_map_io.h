// Reader of Bailey/Nieto simulator maps (datasets/landmark/bailey_sim_maps):
//   #type columns rows
//   lm 2 N     followed by N rows "x y"
//   wp 2 M     followed by M rows "x y"
// Strict: a wrong header, a row count that does not match, a non-finite number or a missing
// section throws InputError naming file, line and field.
#pragma once

#include <Eigen/Core>
#include <istream>
#include <string>
#include <vector>

namespace slamkit {

struct LandmarkMap {
  std::vector<Eigen::Vector2d> landmarks;
  std::vector<Eigen::Vector2d> waypoints;
};

LandmarkMap read_landmark_map(const std::string& path);
LandmarkMap read_landmark_map(std::istream& in, const std::string& source);

}  // namespace slamkit
