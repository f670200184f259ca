#include "optimize_hogman.h"

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "slamkit/factors/hogman.h"
#include "slamkit/io/trajectory_io.h"

namespace slamkit::cli {

void run_hogman_optimize(PoseGraph& g, const HogmanCliOutput& out) {
  HogmanOptions o;
  o.threads = out.threads;
  if (!out.quiet) {
    std::printf("slamkit optimize %s: %zu vertices, %zu edges (%dD), HOG-Man\n", out.input.c_str(), g.vertices().size(),
                g.edges.size(), g.dimension());
    o.stop.callback = [](const RelaxerIteration& it) {
      if (it.iteration == 0) std::printf("%s\n", RelaxerSummary::progress_header().c_str());
      std::printf("%s\n", RelaxerSummary::progress_line(it).c_str());
      std::fflush(stdout);
      return true;
    };
  }
  const RelaxerSummary s = optimize_hogman(g, o);
  std::printf("%s", s.report().c_str());
  if (!out.output.empty()) write_pose_graph(g, out.output, PoseGraphFormat::kAuto, nullptr);
  if (!out.trajectory.empty()) write_trajectory(out.trajectory, to_trajectory(g), TrajectoryFormat::kTum);
  if (!out.json.empty()) {
    nlohmann::json j = nlohmann::json::parse(s.to_json());
    j["label"] = out.label.empty() ? out.input + " (hogman)" : out.label;
    j["file"] = out.input;
    j["format"] = g.format;
    j["vertices"] = g.vertices().size();
    j["edges"] = g.edges.size();
    j["init"] = to_string(o.fine_init);  // the fine level's start (HogmanOptions::fine_init)
    write_json(out.json, j);
  }
}

}  // namespace slamkit::cli
