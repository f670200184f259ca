#include "calibration_cli.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/sim/calibration_generator.h"

namespace slamkit::cli {

void print_calibration(const CalibrationReport& report) {
  for (const std::string& w : report.warnings) std::cerr << "slamkit: warning: " << w << "\n";
  for (const std::string& h : report.held)
    std::cerr << "slamkit: note: " << h << " held at its initial value (unobservable)\n";
  if (report.parameters.empty()) return;
  std::printf("  calibration      %-36s %16s %14s\n", "parameter", "estimate", "sigma");
  for (const CalibrationParameterEstimate& p : report.parameters) {
    if (std::isfinite(p.sigma))
      std::printf("                   %-36s %16.8g %14.4g\n", p.name.c_str(), p.value, p.sigma);
    else
      std::printf("                   %-36s %16.8g %14s\n", p.name.c_str(), p.value, "unobservable");
  }
}

void add_calibration_truth_json(nlohmann::json& j, const std::string& input) {
  CalibrationSimOptions sim;
  if (parse_calibration_sim_spec(input, &sim)) {
    CalibrationTruth truth;
    generate_calibration_problem(sim, &truth);
    nlohmann::json t = nlohmann::json::array();
    for (const auto& [name, value] : truth) t.push_back({{"name", name}, {"value", value}});
    j["calibration_truth"] = t;
  }
}

}  // namespace slamkit::cli
