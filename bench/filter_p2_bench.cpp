// P2 at scale: SEIF with the standard rule vs SEIF with P2's entropy rule (EKF and FastSLAM 2.0
// with 100 particles as the references) on the Bailey webmap and densemap worlds, 30 Monte-Carlo runs each (seeds 1..30,
// the same noise for every filter), active bounds A ∈ {2,4,6,8} (webmap), {4,6,10,15}
// (densemap). Writes bench/results/filters_p2.json, filters_p2.md and one SVG per world.
//   filter_p2_bench [--runs N] [--threads T] [--out DIR] [--worlds webmap,densemap]
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench_data.h"
#include "slamkit/core/string_list.h"
#include "slamkit/eval/filter_consistency.h"
#include "slamkit/eval/filter_plots.h"
#include "slamkit/eval/plot.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/io/landmark_map_io.h"

using namespace slamkit;

int main(int argc, char** argv) {
  int runs = 30, threads = 0;
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results";
  std::vector<std::string> worlds = {"webmap", "densemap"};
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
    else if (!std::strcmp(argv[i], "--worlds")) {
      worlds = split_list(argv[i + 1]);
    }
  }
  const std::map<std::string, std::vector<int>> bounds = {{"webmap", {2, 4, 6, 8}}, {"densemap", {4, 6, 10, 15}}};
  LandmarkSimOptions sim;
  LandmarkFilterOptions fo;
  fo.motion = std::make_shared<BicycleModel>(sim.wheelbase, sim.sigma_v, sim.sigma_steer);
  fo.sensor = RangeBearingModel(sim.sigma_range, sim.sigma_bearing);
  nlohmann::json doc;
  doc["what"] = "P2 at scale: SEIF standard rule vs entropy rule, EKF and FastSLAM 2.0 (100 particles) references; known association";
  doc["particles"] = fo.particles;
  doc["runs"] = runs;
  doc["seeds"] = {1, runs};
  doc["rmse_heading_unit"] = "deg";
  std::ostringstream md;
  md << "# P2 at scale: SEIF vs entropy-SEIF (EKF and FastSLAM 2.0 references)\n\n" << runs
     << " Monte-Carlo runs per row (seeds 1.." << runs << ", identical noise for every filter), known association, "
        "Bailey simulator defaults. ANEES: mean over time of the pose NEES averaged over the runs; 95% bounds ["
     << "see JSON]. RMSE over all runs and observation steps.\n\n";
  for (const std::string& world : worlds) {
    const auto path = bench::data_root() / "landmark/bailey_sim_maps" / ("example_" + world + ".txt");
    const LandmarkMap map = read_landmark_map(path.string());
    nlohmann::json rows = nlohmann::json::array();
    std::map<std::string, ConsistencySummary> keep;
    auto run = [&](const std::string& algorithm, int active) {
      LandmarkFilterOptions f = fo;
      f.active_landmarks = active;
      MonteCarloOptions mc;
      mc.runs = runs;
      mc.threads = threads;
      std::fprintf(stderr, "%s %s A=%d ...\n", world.c_str(), algorithm.c_str(), active);
      const auto results = run_monte_carlo([&] { return make_landmark_filter(algorithm, f); }, map.landmarks,
                                           map.waypoints, sim, mc);
      const ConsistencySummary s = summarize_consistency(results);
      nlohmann::json r = {{"world", world},
                          {"algorithm", algorithm},
                          {"active", active},
                          {"rmse_position", s.rmse_position_total},
                          {"rmse_heading", s.rmse_heading_total * 180 / 3.14159265358979323846},
                          {"anees", s.anees_mean},
                          {"anees_bounds", {s.anees_lo, s.anees_hi}},
                          {"fraction_in_bounds", s.fraction_in_bounds},
                          {"anis", s.anis},
                          {"map_nees", std::isfinite(s.map_nees) ? nlohmann::json(s.map_nees) : nlohmann::json()},
                          {"time_per_step_ms", {{"mean", s.time_per_step_mean_ms}, {"max", s.time_per_step_max_ms}}},
                          {"landmarks", s.landmarks},
                          {"finite", s.finite}};
      std::fprintf(stderr, "  rmse %.3f m  anees %.2f  in-bounds %.1f%%\n", s.rmse_position_total, s.anees_mean,
                   100 * s.fraction_in_bounds);
      rows.push_back(r);
      keep[algorithm + " A=" + std::to_string(active)] = s;
      doc["anees_bounds"] = {s.anees_lo, s.anees_hi};
      return s;
    };
    const ConsistencySummary ekf = run("ekf", 0);
    md << "## " << world << " (" << map.landmarks.size() << " landmarks)\n\n"
       << "| filter | A | pose RMSE [m] | heading RMSE [deg] | ANEES | steps in bounds | ANIS | map NEES |\n"
       << "|---|---|---|---|---|---|---|---|\n";
    char line[256];
    std::snprintf(line, sizeof line, "| EKF (reference) | – | %.3f | %.3f | %.2f | %.1f%% | %.2f | %.2f |\n",
                  ekf.rmse_position_total, ekf.rmse_heading_total * 57.29577951308232, ekf.anees_mean,
                  100 * ekf.fraction_in_bounds, ekf.anis, ekf.map_nees);
    md << line;
    const ConsistencySummary fs2 = run("fastslam2", 0);
    std::snprintf(line, sizeof line, "| FastSLAM 2.0, %d particles (reference) | – | %.3f | %.3f | %.2f | %.1f%% | %.2f | %.2f |\n",
                  fo.particles, fs2.rmse_position_total, fs2.rmse_heading_total * 57.29577951308232, fs2.anees_mean,
                  100 * fs2.fraction_in_bounds, fs2.anis, fs2.map_nees);
    md << line;
    std::vector<double> A, rmse_std, rmse_ent, anees_std, anees_ent;
    for (int active : bounds.at(world)) {
      const ConsistencySummary a = run("seif", active), b = run("seif-entropy", active);
      for (const auto* p : {&a, &b}) {
        std::snprintf(line, sizeof line, "| %s | %d | %.3f | %.3f | %.2f | %.1f%% | %.2f | %.2f |\n",
                      p == &a ? "SEIF" : "entropy-SEIF", active, p->rmse_position_total,
                      p->rmse_heading_total * 57.29577951308232, p->anees_mean, 100 * p->fraction_in_bounds, p->anis,
                      p->map_nees);
        md << line;
      }
      A.push_back(active);
      rmse_std.push_back(a.rmse_position_total);
      rmse_ent.push_back(b.rmse_position_total);
      anees_std.push_back(a.anees_mean);
      anees_ent.push_back(b.anees_mean);
    }
    md << "\n";
    doc[world] = rows;
    // Plots: RMSE and ANEES against A, and ANEES / RMSE over time at the middle bound.
    auto series = [](std::string label, std::vector<double> x, std::vector<double> y, Rgb c, std::string dash = "") {
      Plot::Series s;
      s.label = std::move(label);
      s.x = std::move(x);
      s.y = std::move(y);
      s.color = c;
      s.width = 1.8;
      s.dash = std::move(dash);
      s.points = true;
      return s;
    };
    Plot pr("pose RMSE vs active bound: " + world, "active bound A", "position RMSE [m]");
    pr.set_y_from_zero(true);
    pr.add_series(series("SEIF (standard rule)", A, rmse_std, palette(0)));
    pr.add_series(series("entropy-SEIF (P2)", A, rmse_ent, palette(1)));
    pr.add_hline(ekf.rmse_position_total, "EKF", palette(2));
    pr.add_hline(fs2.rmse_position_total, "FastSLAM 2.0", palette(4));
    Plot pa("ANEES vs active bound: " + world, "active bound A", "ANEES (log scale)");
    pa.set_log_y(true);
    pa.add_band(ekf.anees_lo, ekf.anees_hi, "95% bounds", Rgb{60, 160, 60}, 0.18);
    pa.add_series(series("SEIF (standard rule)", A, anees_std, palette(0)));
    pa.add_series(series("entropy-SEIF (P2)", A, anees_ent, palette(1)));
    pa.add_hline(ekf.anees_mean, "EKF", palette(2));
    pa.add_hline(fs2.anees_mean, "FastSLAM 2.0", palette(4));
    const int mid = bounds.at(world)[1];
    const std::string ks = "seif A=" + std::to_string(mid), ke = "seif-entropy A=" + std::to_string(mid);
    SvgWriter svg(1240, 940);
    svg.embed(pr.render(620, 460), 0, 0);
    svg.embed(pa.render(620, 460), 620, 0);
    svg.embed(plot_anees({{"EKF", &ekf}, {"FastSLAM 2.0", &fs2}, {"SEIF A=" + std::to_string(mid), &keep[ks]},
                          {"entropy-SEIF A=" + std::to_string(mid), &keep[ke]}},
                         "ANEES over time: " + world, 620, 460),
              0, 470);
    svg.embed(plot_rmse({{"EKF", &ekf}, {"FastSLAM 2.0", &fs2}, {"SEIF A=" + std::to_string(mid), &keep[ks]},
                         {"entropy-SEIF A=" + std::to_string(mid), &keep[ke]}},
                        "position RMSE over time: " + world, 620, 460),
              620, 470);
    std::ofstream(out + "/filters_p2_" + world + ".svg") << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" << svg.str();
  }
  std::ofstream(out + "/filters_p2.json") << doc.dump(2) << "\n";
  std::ofstream(out + "/filters_p2.md") << md.str();
  std::cout << md.str();
  return 0;
}
