// slamkit eval ate|rpe EST REF: absolute / relative pose error of an estimate against a
// reference, with evo's definitions (docs/evaluation.md). Prints an evo-style summary,
// optionally writes the run as JSON (--json, the input of `slamkit report`) and an SVG
// figure (--plot).
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/eval/eval_plots.h"
#include "slamkit/eval/evaluation.h"
#include "slamkit/eval/run_json.h"
#include "slamkit/io/trajectory_io.h"

namespace slamkit::cli {

namespace {

struct EvalCliOptions {
  std::string est, ref;
  std::string format = "auto", est_format, ref_format;
  std::string align;  // empty: the metric's default
  std::string relation = "trans_part";
  double t_max_diff = 0.01, t_offset = 0.0;
  std::size_t n_align = 0;
  double delta = 1.0, delta_tol = 0.1;
  std::string delta_unit = "f";
  bool all_pairs = false, pairs_from_reference = false;
  std::string json, plot, label;
};

Trajectory load(const std::string& path, const std::string& format, std::string& used) {
  const TrajectoryFormat f = format == "auto" ? detect_trajectory_format(path) : parse_trajectory_format(format);
  used = to_string(f);
  return read_trajectory(path, f);
}

void print_stats(std::ostream& os, const ErrorStatistics& s) {
  // evo's order and layout.
  const std::pair<const char*, double> rows[] = {{"max", s.max},   {"mean", s.mean}, {"median", s.median},
                                                 {"min", s.min},   {"rmse", s.rmse}, {"sse", s.sse},
                                                 {"std", s.std}};
  for (const auto& [name, v] : rows) os << std::setw(10) << name << "\t" << std::fixed << std::setprecision(6) << v << "\n";
  os.unsetf(std::ios::floatfield);
}

void print_summary(std::ostream& os, const EvalResult& r, const RunSource& src) {
  os << eval_title(r.options) << "\n\n";
  os << "  estimate   " << src.est_path << " (" << src.est_format << ", " << src.est_poses << " poses)\n";
  os << "  reference  " << src.ref_path << " (" << src.ref_format << ", " << src.ref_poses << " poses)\n";
  os << "  matched    " << r.association.size() << " poses ";
  if (r.association.by_index)
    os << "by index\n";
  else
    os << "by timestamp (max. diff. " << r.options.association.max_diff << " s, offset " << r.options.association.offset
       << " s)\n";
  os << "  alignment  " << describe(r.options.align);
  if (r.options.align == AlignmentMode::kSim3 || r.options.align == AlignmentMode::kScale)
    os << ", scale " << std::setprecision(9) << r.alignment.scale;
  os << "\n";
  if (r.options.kind == MetricKind::kRpe) os << "  pairs      " << r.pairs.size() << "\n";
  os << "\n";
  print_stats(os, r.stats);
  os << "\n  parts: translation rmse " << std::setprecision(6) << r.translation_stats.rmse << " m, rotation rmse "
     << r.rotation_stats.rmse << " deg\n";
}

void run_eval(MetricKind kind, const EvalCliOptions& o) {
  check_outputs({{&o.json, "--json"}, {&o.plot, "--plot"}});
  RunSource src;
  src.est_path = o.est;
  src.ref_path = o.ref;
  const Trajectory est = load(o.est, o.est_format.empty() ? o.format : o.est_format, src.est_format);
  const Trajectory ref = load(o.ref, o.ref_format.empty() ? o.format : o.ref_format, src.ref_format);
  src.est_poses = est.size();
  src.ref_poses = ref.size();
  src.label = o.label.empty() ? std::filesystem::path(o.est).filename().string() : o.label;

  EvalOptions opt;
  opt.kind = kind;
  opt.association.max_diff = o.t_max_diff;
  opt.association.offset = o.t_offset;
  opt.align = o.align.empty() ? (kind == MetricKind::kAte ? AlignmentMode::kSe3 : AlignmentMode::kNone)
                              : parse_alignment_mode(o.align);
  opt.n_align = o.n_align;
  opt.relation = parse_pose_relation(o.relation);
  opt.rpe.delta = o.delta;
  opt.rpe.delta_unit = parse_delta_unit(o.delta_unit);
  opt.rpe.rel_tol = o.delta_tol;
  opt.rpe.all_pairs = o.all_pairs;
  opt.rpe.pairs_from_reference = o.pairs_from_reference;

  const EvalResult r = evaluate(est, ref, opt);
  nlohmann::json j = eval_result_to_json(r, src);
  j["slamkit_version"] = SLAMKIT_VERSION;
  print_summary(o.json == "-" ? std::cerr : std::cout, r, src);
  if (!o.json.empty()) write_json(o.json, j);
  if (!o.plot.empty()) {
    const EvalRunData data = eval_run_from_json(j, o.plot);
    write_file_atomically(o.plot, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + eval_figure(data).str(), "plot");
  }
}

void add_metric_command(CLI::App& eval, MetricKind kind) {
  const bool ate = kind == MetricKind::kAte;
  CLI::App* sub = eval.add_subcommand(ate ? "ate" : "rpe",
                                      ate ? "absolute trajectory (pose) error, evo_ape equivalent"
                                          : "relative pose error, evo_rpe equivalent");
  auto o = std::make_shared<EvalCliOptions>();
  sub->add_option("EST", o->est, "estimated trajectory")->required()->check(CLI::ExistingFile);
  sub->add_option("REF", o->ref, "reference (ground-truth) trajectory")->required()->check(CLI::ExistingFile);
  const auto formats = CLI::IsMember({"auto", "tum", "euroc", "asl", "kitti", "slamkit"});
  sub->add_option("--format", o->format, "format of both files (auto: by content / .csv)")->check(formats)
      ->capture_default_str();
  sub->add_option("--est-format", o->est_format, "format of EST (overrides --format)")->check(formats);
  sub->add_option("--ref-format", o->ref_format, "format of REF (overrides --format)")->check(formats);
  sub->add_option("--align", o->align,
                  std::string("alignment of EST to REF (default: ") + (ate ? "se3" : "none") + ")")
      ->check(CLI::IsMember({"se3", "sim3", "4dof", "origin", "scale", "none"}));
  sub->add_option("--n-align", o->n_align, "align with the first N matched poses only (0: all)");
  sub->add_option("-r,--pose-relation", o->relation, "error of the pose part")
      ->check(CLI::IsMember({"trans_part", "angle_deg", "angle_rad", "rot_part", "full", "point_distance"}))
      ->capture_default_str();
  sub->add_option("--t-max-diff", o->t_max_diff, "max. timestamp difference for association [s]")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--t-offset", o->t_offset, "time offset added to EST stamps [s]")->capture_default_str();
  if (!ate) {
    sub->add_option("--delta", o->delta, "step between the poses of a pair")->check(cli::PositiveNumber)
        ->capture_default_str();
    sub->add_option("--delta-unit", o->delta_unit, "f frames, m metres (path), d degrees, r radians, s seconds")
        ->check(CLI::IsMember({"f", "m", "d", "r", "s"}))->capture_default_str();
    sub->add_flag("--all-pairs", o->all_pairs, "use all pairs instead of consecutive ones");
    sub->add_option("--delta-tol", o->delta_tol, "relative tolerance of all-pairs matching")
        ->check(cli::NonNegativeNumber)->capture_default_str();
    sub->add_flag("--pairs-from-reference", o->pairs_from_reference, "select the pairs on REF instead of EST");
  }
  sub->add_option("--json", o->json, "write the run as JSON ('-': stdout); input of `slamkit report`");
  sub->add_option("--plot", o->plot, "write an SVG figure (trajectories, errors, histogram)");
  sub->add_option("--label", o->label, "name of the run in plots and reports (default: EST's file name)");
  sub->callback([kind, o]() { run_eval(kind, *o); });
}

}  // namespace

void add_eval_command(CLI::App& app) {
  CLI::App* eval = app.add_subcommand("eval", "trajectory evaluation: ATE and RPE as evo computes them");
  eval->require_subcommand(1);
  add_metric_command(*eval, MetricKind::kAte);
  add_metric_command(*eval, MetricKind::kRpe);
}

}  // namespace slamkit::cli
