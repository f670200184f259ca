// The standard figures of trajectory evaluation, drawn from eval run documents (run_json.h)
// so that `slamkit eval --plot` and `slamkit report` show the same pictures:
//   trajectory views   estimate(s) over the reference, top view (the plane of the two axes
//                      along which the reference spreads most) and side view (the widest axis
//                      against the narrowest); equal aspect.
//   error over time    per-pair errors vs time (or index without timestamps); for one run
//                      with its rmse, mean, median and a mean ± std band, as evo draws them.
//   error along path   the estimate coloured by its error (viridis + colour bar) over the
//                      reference (dashed grey).
//   histogram          distribution of the errors, one translucent layer per run.
// Runs are coloured by their position in the list (palette()). Pure functions.
#pragma once

#include <vector>

#include "slamkit/eval/run_json.h"
#include "slamkit/eval/svg.h"

namespace slamkit {

enum class TrajectoryView { kTop, kSide };

SvgWriter plot_trajectories(const std::vector<const EvalRunData*>& runs, TrajectoryView view, double width,
                            double height);
SvgWriter plot_error_over_time(const std::vector<const EvalRunData*>& runs, double width, double height);
SvgWriter plot_error_along_path(const EvalRunData& run, double width, double height);
SvgWriter plot_error_histogram(const std::vector<const EvalRunData*>& runs, double width, double height);

/// All figures of one run on one page (the --plot output), with a header line of statistics.
SvgWriter eval_figure(const EvalRunData& run);

}  // namespace slamkit
