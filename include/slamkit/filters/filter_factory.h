// One place that builds a LandmarkFilter by name, so the CLI, the Monte-Carlo runner and the
// benchmarks treat every filter alike: "ekf", "eif", "seif", "seif-entropy", and the FastSLAM
// variants once their branch is merged (one line each in filter_factory.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slamkit/filters/landmark_filter.h"
#include "slamkit/filters/seif.h"

namespace slamkit {

/// Throws InputError naming the algorithm when it is unknown or not built.
std::unique_ptr<LandmarkFilter> make_landmark_filter(const std::string& name, const LandmarkFilterOptions& options,
                                                     const SeifOptions& seif = {});
/// The names make_landmark_filter accepts (including those not built, for the help text).
std::vector<std::string> landmark_filter_names();

}  // namespace slamkit
