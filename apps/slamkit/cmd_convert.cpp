// slamkit convert IN OUT: rewrite a pose graph in another format.
//
// The output format comes from OUT's extension (.g2o, .graph = TORO, .txt = GTSAM EDGE3)
// unless --to names it. Information matrices are converted between the formats'
// conventions (docs/formats.md). A conversion the target cannot represent (landmarks in
// TORO, a 2D graph in GTSAM EDGE3) fails before anything is written; elements the target
// has no tag for (EQUIV, FIX) are dropped with a warning on stderr.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/core/error.h"
#include "slamkit/io/pose_graph_io.h"

namespace slamkit::cli {

namespace {

struct ConvertOptions {
  std::string input, output;
  std::string from = "auto", to = "auto";
  bool repair_information = false;
  bool allow_unknown_tags = false;
  bool keep_edges_only = false;
};

void run_convert(const ConvertOptions& o) {
  PoseGraphFormat target = parse_pose_graph_format(o.to);
  if (target == PoseGraphFormat::kAuto) {
    target = format_from_extension(o.output);
    if (target == PoseGraphFormat::kAuto)
      throw InputError(o.output, 0, "", "cannot tell the output format from the extension; use --to g2o|toro|gtsam");
  }
  check_outputs({{&o.output, "output"}});
  PoseGraphReadOptions read;
  read.format = parse_pose_graph_format(o.from);
  read.repair_information = o.repair_information;
  read.unknown_tags_as_warnings = o.allow_unknown_tags;
  read.complete_estimates = !o.keep_edges_only;
  PoseGraphReadReport report;
  const PoseGraph g = load_pose_graph(o.input, read, &report);
  std::vector<std::string> warnings = report.warnings;
  if (report.information.bad() > 0 && !o.repair_information) {
    warnings.push_back(std::to_string(report.information.bad()) +
                       " information matrices are not positive definite (first on line " +
                       std::to_string(report.information.first_bad_line) + "); written as they are");
  }
  write_pose_graph(g, o.output, target, &warnings);
  for (const std::string& w : warnings) std::cerr << "slamkit: warning: " << w << "\n";

  std::cout << "converted " << o.input << " (" << to_string(report.format) << ", " << g.dimension() << "D, "
            << g.vertices().size() << " vertices, " << g.edges.size() << " edges) -> " << o.output << " ("
            << to_string(target) << ")\n";
  if (report.completed_estimates > 0) {
    std::cout << "  edges-only input: " << report.completed_estimates
              << " vertex estimates written from odometry composition (--keep-edges-only to omit them)\n";
  }
  if (report.repaired_information > 0)
    std::cout << "  " << report.repaired_information << " information matrices projected to the PSD cone\n";
}

}  // namespace

void add_convert_command(CLI::App& app) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* cmd = app.add_subcommand("convert", "Convert a pose graph between g2o, TORO and GTSAM EDGE3 text");
  cmd->add_option("input", o->input, "input pose-graph file")->required();
  cmd->add_option("output", o->output, "output file (format from the extension unless --to)")->required();
  const auto formats = CLI::IsMember({"auto", "g2o", "toro", "gtsam"}, CLI::ignore_case);
  cmd->add_option("--to", o->to, "output format")->check(formats);
  cmd->add_option("--from", o->from, "input format instead of detecting it")->check(formats);
  cmd->add_flag("--repair-information", o->repair_information,
                "project information matrices that are not positive definite to the PSD cone");
  cmd->add_flag("--allow-unknown-tags", o->allow_unknown_tags, "skip unknown tags with a warning instead of failing");
  cmd->add_flag("--keep-edges-only", o->keep_edges_only,
                "for an edges-only input, write no vertex lines (instead of odometry-composed estimates)");
  cmd->callback([o]() { run_convert(*o); });
}

}  // namespace slamkit::cli
