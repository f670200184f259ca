// slamkit filter: runs a landmark-SLAM filter (EKF, EIF, SEIF, entropy-SEIF, FastSLAM 1.0/2.0)
// on a simulated 2-D landmark world N times (seeds S..S+N−1, the same noise draws for every
// filter), and reports pose RMSE, ANEES with its χ² bounds, NIS, map NEES and time per
// step (docs/filters.md). --json is the input of `slamkit report`.
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/core/path_query.h"
#include "slamkit/eval/filter_consistency.h"
#include "slamkit/eval/filter_dataset.h"
#include "slamkit/eval/filter_plots.h"
#include "slamkit/filters/chi_square.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/io/landmark_map_io.h"

namespace slamkit::cli {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct FilterCliOptions {
  std::string algorithm, world = "webmap", dataset, association = "known";
  int runs = 1, active = 6, particles = 100, threads = 0, laps = 1, steps = 0;
  std::uint64_t seed = 1;
  std::string json, plot, trajectory, label;
};

// A Bailey map by name (webmap, densemap, ...) under $SLAMKIT_DATA, a map FILE, or generated:N.
std::string resolve_world(const std::string& world, LandmarkMap* map) {
  if (world.rfind("generated:", 0) == 0) {
    const std::string n_text = world.substr(10);
    char* end = nullptr;
    const long n = std::strtol(n_text.c_str(), &end, 10);
    if (n_text.empty() || *end != '\0' || n < 1 || n > 1000000)
      throw InputError("--world", 0, "world", "generated:N needs a landmark count 1..1000000, got \"" + n_text + "\"");
    generate_landmark_world(int(n), 1, &map->landmarks, &map->waypoints);
    return world;
  }
  std::string path = world;
  if (!path_exists(path) && world.find('/') == std::string::npos && world.find('.') == std::string::npos) {
    const char* data = std::getenv("SLAMKIT_DATA");
    if (!data)
      throw InputError("--world", 0, "world", "\"" + world + "\" is a Bailey map name: set SLAMKIT_DATA to the datasets folder, or give the map FILE");
    path = std::string(data) + "/landmark/bailey_sim_maps/example_" + world + ".txt";
    if (!path_exists(path))
      throw InputError(path, 0, "world", "no such map (names: webmap, densemap, linemap, smallmap, loop1, loop2, loop902)");
  }
  *map = read_landmark_map(path);
  return path;
}

std::string tum_line(double t, const Eigen::Vector3d& p) {
  std::ostringstream os;
  os << std::setprecision(10) << t << ' ' << p.x() << ' ' << p.y() << " 0 0 0 " << std::sin(p.z() / 2) << ' '
     << std::cos(p.z() / 2) << '\n';
  return os.str();
}

void progress_bar(int done, int total) {
  const int width = 30, filled = width * done / total;
  std::cerr << "\r  runs [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done << "/"
            << total << std::flush;
  if (done == total) std::cerr << "\n";
}

nlohmann::json nullable(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// --dataset: one run of the filter over a real event stream (eval/filter_dataset.h).
// The run's name in reports, and the JSON fields every filter document starts with.
std::string run_label(const FilterCliOptions& o) {
  if (!o.label.empty()) return o.label;
  return o.algorithm + (o.algorithm.rfind("seif", 0) == 0 ? " A=" + std::to_string(o.active) : "");
}
nlohmann::json filter_json_head(const FilterCliOptions& o) {
  return {{"kind", "filter"}, {"schema", 1}, {"label", run_label(o)}, {"algorithm", o.algorithm},
          {"association", o.association}, {"seed", o.seed}, {"active", o.active}, {"particles", o.particles}};
}

void run_filter_on_dataset_command(const FilterCliOptions& o) {
  if (o.runs != 1) throw InputError("--runs", 0, "runs", "a dataset is one run: --runs must be 1 with --dataset");
  if (o.active < 1) throw InputError("--active", 0, "active", "must be >= 1");
  if (o.particles < 1) throw InputError("--particles", 0, "particles", "must be >= 1");
  const LandmarkDataset ds = load_landmark_dataset(o.dataset);
  const DatasetModels models = dataset_models(ds);
  LandmarkFilterOptions fo;
  fo.motion = models.motion;
  fo.sensor = models.sensor;
  fo.initial_pose = ds.initial_pose;
  fo.association.method = parse_association_method(o.association);
  fo.active_landmarks = o.active;
  fo.particles = o.particles;
  fo.seed = o.seed;
  auto filter = make_landmark_filter(o.algorithm, fo);
  std::ostream& out = o.json == "-" ? std::cerr : std::cout;
  out << "slamkit filter: " << o.algorithm << " on " << ds.name << " (" << ds.events.size() << " events), association "
      << o.association << "\n  models        " << models.description << "\n" << std::flush;
  DatasetRunOptions ro;
  ro.progress = [&](int done, int total, int lm, double ms) {
    out << "  scan " << done << "/" << total << ", " << lm << " landmarks, " << std::setprecision(4) << ms
        << " ms/step so far\n" << std::flush;
  };
  Stopwatch clock;
  const DatasetRunResult r = run_filter_on_dataset(filter.get(), *models.motion, ds, ro);
  const double wall = clock.seconds();
  const bool truth = std::isfinite(r.rmse_position);
  // One run: the NEES mean over the scans has the χ²₃ bounds of N = 1.
  const double nees_lo = chi2_quantile(0.025, 3), nees_hi = chi2_quantile(0.975, 3);
  int inside = 0, nees_n = 0;
  for (double e : r.run.nees)
    if (std::isfinite(e)) ++nees_n, inside += (e >= nees_lo && e <= nees_hi);
  out << std::fixed << std::setprecision(3);
  out << "  steps         " << r.events << " events, " << r.scans << " scans, " << r.landmarks << " landmarks mapped\n";
  if (truth) {
    out << "  pose RMSE     " << r.rmse_position << " m, " << r.rmse_heading * 180 / kPi << " deg (dead reckoning "
        << r.dead_reckoning_rmse_position << " m)\n";
    out << "  mean NEES     " << r.mean_nees << " over " << r.nees_scans << " scans (chi2_3 95%: [" << nees_lo << ", "
        << nees_hi << "])\n";
  }
  if (std::isfinite(r.map_rmse)) out << "  map RMSE      " << r.map_rmse << " m over " << r.mapped_true_landmarks << " surveyed landmarks\n";
  if (std::isfinite(r.gps_rms))
    out << "  GPS           " << r.gps_rms << " m RMS after alignment (dead reckoning " << r.dead_reckoning_gps_rms
        << " m), " << r.gps_matched << " fixes\n";
  out << "  time/step     " << std::setprecision(4) << r.time_per_step_mean_ms << " ms mean, " << r.time_per_step_max_ms
      << " ms max (wall " << std::setprecision(1) << wall << " s)\n";
  if (!r.run.finite) out << "  WARNING: a non-finite estimate or covariance occurred\n";
  out.unsetf(std::ios::floatfield);

  if (!o.json.empty()) {
    nlohmann::json j = filter_json_head(o);
    j["dataset"] = ds.name;
    j["dataset_spec"] = o.dataset;
    j["models"] = models.description;
    j["runs"] = 1;
    j["landmarks"] = r.landmarks;
    j["events"] = r.events;
    j["scans"] = r.scans;
    j["steps"] = r.events;
    j["rmse_position"] = nullable(r.rmse_position);
    j["rmse_heading"] = truth ? nlohmann::json(r.rmse_heading * 180 / kPi) : nlohmann::json(nullptr);
    j["rmse_heading_unit"] = "deg";
    j["dead_reckoning_rmse_position"] = nullable(r.dead_reckoning_rmse_position);
    j["anees"] = nullable(r.mean_nees);
    j["anees_bounds"] = {nees_lo, nees_hi};
    j["confidence"] = 0.95;
    j["fraction_in_bounds"] = nees_n > 0 ? nlohmann::json(double(inside) / nees_n) : nlohmann::json(nullptr);
    j["nees_scans"] = r.nees_scans;
    j["map_rmse"] = nullable(r.map_rmse);
    j["gps_rms_after_alignment"] = nullable(r.gps_rms);
    j["dead_reckoning_gps_rms_after_alignment"] = nullable(r.dead_reckoning_gps_rms);
    j["time_per_step_ms"] = {{"mean", r.time_per_step_mean_ms}, {"max", r.time_per_step_max_ms}};
    j["time_per_scan_ms"] = r.time_per_scan_ms;
    j["finite"] = r.run.finite;
    j["slamkit_version"] = SLAMKIT_VERSION;
    write_json(o.json, j);
  }
  if (!o.plot.empty())
    write_file_atomically(o.plot, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + plot_dataset_run(run_label(o), r, ds).str(), "--plot");
  if (!o.trajectory.empty()) {
    std::string text = "# timestamp x y z qx qy qz qw  (slamkit filter " + o.algorithm + " on " + ds.name + ", at the scans)\n";
    for (std::size_t k = 0; k < r.run.time.size(); ++k) text += tum_line(r.run.time[k], r.run.estimate[k]);
    write_file_atomically(o.trajectory, text, "--trajectory");
  }
}

void run_filter_command(const FilterCliOptions& o) {
  check_outputs({{&o.json, "--json"}, {&o.plot, "--plot"}, {&o.trajectory, "--trajectory"}});
  if (!o.dataset.empty()) return run_filter_on_dataset_command(o);
  if (o.runs < 1) throw InputError("--runs", 0, "runs", "must be >= 1");
  if (o.active < 1) throw InputError("--active", 0, "active", "must be >= 1");
  if (o.particles < 1) throw InputError("--particles", 0, "particles", "must be >= 1");

  LandmarkMap map;
  const std::string world_source = resolve_world(o.world, &map);
  LandmarkSimOptions sim;
  sim.laps = o.laps;
  sim.max_steps = o.steps;
  LandmarkFilterOptions fo;
  fo.motion = std::make_shared<BicycleModel>(sim.wheelbase, sim.sigma_v, sim.sigma_steer);
  fo.sensor = RangeBearingModel(sim.sigma_range, sim.sigma_bearing);
  fo.association.method = parse_association_method(o.association);
  fo.association.candidate_range = sim.max_range + 10.0;
  fo.active_landmarks = o.active;
  fo.particles = o.particles;
  fo.seed = o.seed;
  make_landmark_filter(o.algorithm, fo);  // an unknown or unbuilt algorithm fails before the work
  const bool known = fo.association.method == AssociationMethod::kKnown;

  std::ostream& out = o.json == "-" ? std::cerr : std::cout;
  out << "slamkit filter: " << o.algorithm << " on " << world_source << " (" << map.landmarks.size()
      << " landmarks, " << map.waypoints.size() << " waypoints), association " << o.association << ", " << o.runs
      << " run" << (o.runs == 1 ? "" : "s") << " (seeds " << o.seed << ".." << o.seed + o.runs - 1 << ")";
  if (o.algorithm.rfind("seif", 0) == 0) out << ", active bound " << o.active;
  out << "\n" << std::flush;

  MonteCarloOptions mc;
  mc.runs = o.runs;
  mc.first_seed = o.seed;
  mc.threads = o.threads;
  mc.run.map_nees = known;
  mc.progress = progress_bar;
  Stopwatch clock;
  const std::vector<FilterRunResult> runs = run_monte_carlo(
      [&] { return make_landmark_filter(o.algorithm, fo); }, map.landmarks, map.waypoints, sim, mc);
  const ConsistencySummary s = summarize_consistency(runs);
  const double wall = clock.seconds();

  out << std::fixed << std::setprecision(3);
  out << "  steps         " << runs.front().step_ms.size() << " controls, " << s.time.size() << " observation steps, "
      << s.landmarks << " landmarks mapped\n";
  out << "  pose RMSE     " << s.rmse_position_total << " m, " << s.rmse_heading_total * 180 / kPi << " deg\n";
  out << "  ANEES         " << s.anees_mean << "  (95% bounds for " << s.runs << " runs: [" << s.anees_lo << ", "
      << s.anees_hi << "], " << std::setprecision(1) << 100 * s.fraction_in_bounds << "% of steps inside)\n"
      << std::setprecision(3);
  out << "  ANIS          " << s.anis << " (per dof; 1 when consistent)\n";
  if (std::isfinite(s.map_nees)) out << "  map NEES      " << s.map_nees << " (per landmark, 2 dof)\n";
  out << "  time/step     " << std::setprecision(4) << s.time_per_step_mean_ms << " ms mean, " << s.time_per_step_max_ms
      << " ms max (wall " << std::setprecision(1) << wall << " s)\n";
  if (!s.finite) out << "  WARNING: a non-finite estimate or covariance occurred\n";
  out.unsetf(std::ios::floatfield);

  if (!o.json.empty()) {
    nlohmann::json j = filter_json_head(o);
    j["world"] = o.world;
    j["world_source"] = world_source;
    j["runs"] = o.runs;
    j["landmarks"] = s.landmarks;
    j["world_landmarks"] = map.landmarks.size();
    j["steps"] = runs.front().step_ms.size();
    j["rmse_position"] = s.rmse_position_total;
    j["rmse_heading"] = s.rmse_heading_total * 180 / kPi;
    j["rmse_heading_unit"] = "deg";
    j["anees"] = s.anees_mean;
    j["anees_bounds"] = {s.anees_lo, s.anees_hi};
    j["confidence"] = s.confidence;
    j["fraction_in_bounds"] = s.fraction_in_bounds;
    j["anis"] = std::isfinite(s.anis) ? nlohmann::json(s.anis) : nlohmann::json(nullptr);
    j["map_nees"] = std::isfinite(s.map_nees) ? nlohmann::json(s.map_nees) : nlohmann::json(nullptr);
    j["time_per_step_ms"] = {{"mean", s.time_per_step_mean_ms}, {"max", s.time_per_step_max_ms}};
    j["finite"] = s.finite;
    j["series"] = {{"time", s.time}, {"anees", s.anees}, {"rmse_position", s.rmse_position},
                   {"rmse_heading_deg", [&] {
                      std::vector<double> d;
                      for (double r : s.rmse_heading) d.push_back(r * 180 / kPi);
                      return d;
                    }()}};
    j["slamkit_version"] = SLAMKIT_VERSION;
    write_json(o.json, j);
  }
  if (!o.plot.empty())
    write_file_atomically(o.plot, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" +
                                      filter_dashboard(run_label(o), runs.front(), s, map.landmarks).str(), "--plot");
  if (!o.trajectory.empty()) {
    std::string text = "# timestamp x y z qx qy qz qw  (slamkit filter " + o.algorithm + ", seed " +
                       std::to_string(runs.front().seed) + ")\n";
    for (std::size_t k = 0; k < runs.front().time.size(); ++k) text += tum_line(runs.front().time[k], runs.front().estimate[k]);
    write_file_atomically(o.trajectory, text, "--trajectory");
  }
}

}  // namespace

void add_filter_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("filter", "landmark-SLAM filters (EKF, EIF, SEIF, entropy-SEIF, FastSLAM 1.0/2.0) with Monte-Carlo consistency statistics");
  auto o = std::make_shared<FilterCliOptions>();
  sub->add_option("--algorithm", o->algorithm, "ekf | eif | seif | seif-entropy | fastslam1 | fastslam2")
      ->required()->check(CLI::IsMember(landmark_filter_names()));
  sub->add_option("--world", o->world, "webmap | densemap | linemap | smallmap | FILE | generated:N")->capture_default_str();
  sub->add_option("--dataset", o->dataset, "mrclam:DIR:ROBOT | victoria:DIR: one run on a real dataset instead of --world");
  sub->add_option("--association", o->association, "data association")->check(CLI::IsMember({"known", "nn", "jcbb"}))
      ->capture_default_str();
  sub->add_option("--runs", o->runs, "Monte-Carlo runs")->capture_default_str();
  sub->add_option("--seed", o->seed, "first seed (runs use seed .. seed+runs-1)")->capture_default_str();
  sub->add_option("--active", o->active, "SEIF active-landmark bound")->capture_default_str();
  sub->add_option("--particles", o->particles, "FastSLAM particles")->capture_default_str();
  sub->add_option("--laps", o->laps, "laps over the waypoints")->check(cli::PositiveNumber)->capture_default_str();
  sub->add_option("--steps", o->steps, "stop after this many control steps (0: the whole route)")
      ->check(cli::NonNegativeNumber);
  sub->add_option("--threads", o->threads, "worker threads for the runs (0: all cores)");
  sub->add_option("--json", o->json, "write the summary as JSON ('-': stdout); input of `slamkit report`");
  sub->add_option("--plot", o->plot, "write an SVG dashboard (map with 3σ ellipses, error ±3σ, ANEES, RMSE)");
  sub->add_option("--trajectory", o->trajectory, "write the first run's estimate as TUM");
  sub->add_option("--label", o->label, "name of the run in reports");
  sub->callback([o]() { run_filter_command(*o); });
}

}  // namespace slamkit::cli
