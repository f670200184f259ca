// pose_graph_result_to_json: the one place that turns a PoseGraphResult into the documented
// `slamkit optimize --json` fields (docs/evaluation.md), shared by the CLI and Python.
#include <cmath>
#include <nlohmann/json.hpp>

#include "slamkit/factors/pose_graph_optimizer.h"

namespace slamkit {

std::string pose_graph_result_to_json(const PoseGraphResult& r, const PoseGraph& g) {
  nlohmann::json j = nlohmann::json::parse(r.summary.to_json());
  j["format"] = g.format;
  j["dimension"] = g.dimension();
  j["vertices"] = g.vertices().size();
  j["edges"] = g.edges.size();
  j["init"] = to_string(r.init.used);
  j["init_requested"] = to_string(r.init.requested);
  j["initial_chi2"] = r.input_chi2;
  j["chi2_after_init"] = r.chi2_after_init;
  j["optimizer_initial_cost"] = r.summary.initial_cost;
  j["final_cost"] = r.summary.final_cost;
  j["final_chi2"] = r.final_chi2;
  j["time_init_s"] = r.init.time_s;
  j["time_ordering_s"] = r.time_ordering_s;
  j["time_optimize_s"] = r.summary.time_total_s;
  j["time_total_s"] = r.time_total_s;  // end to end: ordering + initialization + optimization
  j["time_end_to_end_s"] = r.time_total_s;
  j["notes"] = r.notes;
  if (!r.calibration.parameters.empty() || !r.calibration.warnings.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const CalibrationParameterEstimate& p : r.calibration.parameters) {
      nlohmann::json e = {{"name", p.name}, {"value", p.value}, {"observable", p.observable}};
      e["sigma"] = std::isfinite(p.sigma) ? nlohmann::json(p.sigma) : nlohmann::json(nullptr);  // unobservable
      list.push_back(e);
    }
    j["calibration"] = list;
    j["calibration_warnings"] = r.calibration.warnings;
  }
  return j.dump();
}

}  // namespace slamkit
