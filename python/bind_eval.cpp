// Bindings of slamkit/eval: association, alignment, ATE/RPE with evo's definitions and
// statistics, per-pair errors as arrays, the run JSON document, SVG figures and the HTML report.
#include <fstream>
#include <nlohmann/json.hpp>

#include "bind_common.h"
#include "slamkit/core/error.h"
#include "slamkit/eval/eval_plots.h"
#include "slamkit/eval/evaluation.h"
#include "slamkit/eval/report.h"
#include "slamkit/eval/run_json.h"
#include "slamkit/eval/statistics.h"

namespace slamkit::python {
namespace {

py::object json_to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

nlohmann::json python_to_json(const py::handle& obj, const std::string& source) {
  const std::string text = py::str(py::module_::import("json").attr("dumps")(obj));
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, 0, "", std::string("not valid JSON: ") + e.what());
  }
}

py::array_t<std::uint64_t> pairs_array(const IndexPairs& p) {
  py::array_t<std::uint64_t> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{2}});
  auto u = a.mutable_unchecked<2>();
  for (std::size_t k = 0; k < p.size(); ++k) u(k, 0) = p[k].first, u(k, 1) = p[k].second;
  return a;
}

py::dict stats_dict(const ErrorStatistics& s) {
  py::dict d;
  d["rmse"] = s.rmse, d["mean"] = s.mean, d["median"] = s.median, d["std"] = s.std;
  d["min"] = s.min, d["max"] = s.max, d["sse"] = s.sse, d["count"] = s.count;
  return d;
}

RpeOptions rpe_options(double delta, const std::string& unit, double rel_tol, bool all_pairs, bool from_ref,
                       const std::string& relation) {
  require_finite(delta, "delta"), require_finite(rel_tol, "delta_tol");
  RpeOptions o;
  o.delta = delta;
  o.delta_unit = parse_delta_unit(unit);
  o.rel_tol = rel_tol;
  o.all_pairs = all_pairs;
  o.pairs_from_reference = from_ref;
  o.relation = parse_pose_relation(relation);
  return o;
}

RunSource run_source(const EvalResult& r, const std::string& label, const std::string& est_path,
                     const std::string& ref_path) {
  RunSource s;
  s.label = label.empty() ? (est_path.empty() ? "estimate" : est_path) : label;
  s.est_path = est_path, s.ref_path = ref_path;
  s.est_poses = r.est.size(), s.ref_poses = r.ref.size();
  return s;
}

EvalResult run_evaluate(const Trajectory& est, const Trajectory& ref, const std::string& metric,
                        const py::object& align, const std::string& relation, double max_diff, double offset,
                        std::size_t n_align, double delta, const std::string& delta_unit, bool all_pairs,
                        double delta_tol, bool pairs_from_reference) {
  require_finite(max_diff, "max_diff"), require_finite(offset, "offset");
  EvalOptions o;
  if (metric == "ate" || metric == "ape")
    o.kind = MetricKind::kAte;
  else if (metric == "rpe")
    o.kind = MetricKind::kRpe;
  else
    throw InputError("", 0, "metric", "expected 'ate' or 'rpe', got '" + metric + "'");
  o.association.max_diff = max_diff;
  o.association.offset = offset;
  // The CLI's defaults: SE(3) alignment for ATE, none for RPE.
  o.align = align.is_none() ? (o.kind == MetricKind::kAte ? AlignmentMode::kSe3 : AlignmentMode::kNone)
                            : parse_alignment_mode(align.cast<std::string>());
  o.n_align = n_align;
  o.relation = parse_pose_relation(relation);
  o.rpe = rpe_options(delta, delta_unit, delta_tol, all_pairs, pairs_from_reference, relation);
  py::gil_scoped_release release;
  return evaluate(est, ref, o);
}

// Run documents (EvalResult objects or dicts such as EvalResult.to_dict()) for the plots.
std::vector<EvalRunData> run_data(const py::list& runs) {
  std::vector<EvalRunData> data;
  std::size_t k = 0;
  for (py::handle run : runs) {
    const std::string source = "runs[" + std::to_string(k++) + "]";
    if (py::isinstance<EvalResult>(run)) {
      const EvalResult& r = run.cast<const EvalResult&>();
      data.push_back(eval_run_from_json(eval_result_to_json(r, run_source(r, source, "", "")), source));
    } else {
      data.push_back(eval_run_from_json(python_to_json(run, source), source));
    }
  }
  if (data.empty()) throw py::value_error("plot: no runs");
  return data;
}

std::vector<const EvalRunData*> pointers(const std::vector<EvalRunData>& d) {
  std::vector<const EvalRunData*> p;
  for (const auto& r : d) p.push_back(&r);
  return p;
}

void check_size(double w, double h) {
  if (!(w >= 50 && h >= 50 && w <= 1e5 && h <= 1e5)) throw py::value_error("plot: width and height in [50, 1e5]");
}

}  // namespace

void init_eval(py::module_& m) {
  py::class_<ErrorStatistics>(m, "ErrorStatistics",
                              "evo's statistics: rmse, mean, median, std (population), min, max, sse, count.")
      .def_readonly("rmse", &ErrorStatistics::rmse)
      .def_readonly("mean", &ErrorStatistics::mean)
      .def_readonly("median", &ErrorStatistics::median)
      .def_readonly("std", &ErrorStatistics::std)
      .def_readonly("min", &ErrorStatistics::min)
      .def_readonly("max", &ErrorStatistics::max)
      .def_readonly("sse", &ErrorStatistics::sse)
      .def_readonly("count", &ErrorStatistics::count)
      .def("to_dict", &stats_dict, "The statistics as a dict.")
      .def("__repr__", [](const ErrorStatistics& s) {
        return "ErrorStatistics(rmse=" + std::to_string(s.rmse) + ", mean=" + std::to_string(s.mean) +
               ", count=" + std::to_string(s.count) + ")";
      });
  m.def(
      "compute_statistics",
      [](const py::handle& e) {
        const Eigen::VectorXd v = to_vector(e, -1, "errors");
        if (v.size() == 0) throw py::value_error("compute_statistics: empty input");
        return compute_statistics(std::vector<double>(v.data(), v.data() + v.size()));
      },
      py::arg("errors"), "evo's statistics of an error array.");

  py::class_<Association>(m, "Association", "est_ids[k] is matched with ref_ids[k].")
      .def_property_readonly("est_ids", [](const Association& a) { return to_array(a.est_ids); })
      .def_property_readonly("ref_ids", [](const Association& a) { return to_array(a.ref_ids); })
      .def_readonly("by_index", &Association::by_index)
      .def("__len__", &Association::size);
  m.def(
      "associate",
      [](const Trajectory& est, const Trajectory& ref, double max_diff, double offset) {
        require_finite(max_diff, "max_diff"), require_finite(offset, "offset");
        AssociationOptions o;
        o.max_diff = max_diff;
        o.offset = offset;
        return associate(est, ref, o);
      },
      py::arg("est"), py::arg("ref"), py::arg("max_diff") = 0.01, py::arg("offset") = 0.0,
      "evo's association: nearest stamp within max_diff [s] (offset added to est), by index without stamps.");
  m.def(
      "compute_alignment",
      [](const Trajectory& est, const Trajectory& ref, const std::string& mode, std::size_t n_first) {
        return compute_alignment(est, ref, parse_alignment_mode(mode), n_first);
      },
      py::arg("est"), py::arg("ref"), py::arg("mode") = "se3", py::arg("n_first") = 0,
      "S taking the associated est onto ref: 'none' | 'origin' | 'se3' | 'sim3' | '4dof' | 'scale'.");
  m.def("apply_alignment", &apply_alignment, py::arg("est"), py::arg("alignment"),
        "est with S applied from the left to every pose (p' = s R p + t).");

  py::class_<PoseErrors>(m, "PoseErrors", "Per-pair errors: the chosen relation and the two standard parts.")
      .def_property_readonly("errors", [](const PoseErrors& e) { return to_array(e.errors); })
      .def_property_readonly("translation", [](const PoseErrors& e) { return to_array(e.translation); }, "[m]")
      .def_property_readonly("rotation_deg", [](const PoseErrors& e) { return to_array(e.rotation_deg); }, "[deg]");
  py::class_<RpeErrors, PoseErrors>(m, "RpeErrors", "RPE errors with the index pairs they belong to.")
      .def_property_readonly("pairs", [](const RpeErrors& e) { return pairs_array(e.pairs); }, "K×2 (i, j).");
  m.def(
      "compute_ate",
      [](const Trajectory& est, const Trajectory& ref, const std::string& relation) {
        return compute_ate(est, ref, parse_pose_relation(relation));
      },
      py::arg("est"), py::arg("ref"), py::arg("relation") = "trans_part",
      "ATE of associated, aligned trajectories: E_k = P_k^-1 Q_k. relation: 'trans_part' | 'angle_deg' | "
      "'angle_rad' | 'rot_part' | 'full' | 'point_distance'.");
  m.def(
      "compute_rpe",
      [](const Trajectory& est, const Trajectory& ref, double delta, const std::string& unit, double rel_tol,
         bool all_pairs, bool from_ref, const std::string& relation) {
        return compute_rpe(est, ref, rpe_options(delta, unit, rel_tol, all_pairs, from_ref, relation));
      },
      py::arg("est"), py::arg("ref"), py::arg("delta") = 1.0, py::arg("delta_unit") = "f", py::arg("delta_tol") = 0.1,
      py::arg("all_pairs") = false, py::arg("pairs_from_reference") = false, py::arg("relation") = "trans_part",
      "RPE over pairs (i, j): E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j). delta_unit 'f' | 'm' | 'd' | 'r' | 's'.");
  m.def(
      "select_pairs",
      [](const Trajectory& t, double delta, const std::string& unit, bool all_pairs, double rel_tol) {
        require_finite(delta, "delta");
        return pairs_array(select_pairs(t, delta, parse_delta_unit(unit), all_pairs, rel_tol));
      },
      py::arg("trajectory"), py::arg("delta") = 1.0, py::arg("delta_unit") = "f", py::arg("all_pairs") = false,
      py::arg("delta_tol") = 0.1, "The RPE pairs (K×2) of a trajectory, with evo's rules.");

  py::class_<EvalResult>(m, "EvalResult", "The result of evaluate(): statistics, per-pair errors, alignment.")
      .def_readonly("association", &EvalResult::association)
      .def_readonly("alignment", &EvalResult::alignment, "Similarity3 applied to the estimate.")
      .def_readonly("est", &EvalResult::est, "Associated and aligned estimate.")
      .def_readonly("ref", &EvalResult::ref, "Associated reference.")
      .def_property_readonly("errors", [](const EvalResult& r) { return to_array(r.errors.errors); },
                             "Per-pair errors of the chosen relation.")
      .def_property_readonly("translation_errors", [](const EvalResult& r) { return to_array(r.errors.translation); })
      .def_property_readonly("rotation_errors_deg",
                             [](const EvalResult& r) { return to_array(r.errors.rotation_deg); })
      .def_property_readonly("pairs", [](const EvalResult& r) { return pairs_array(r.pairs); }, "RPE only.")
      .def_property_readonly("error_index", [](const EvalResult& r) { return to_array(r.error_index); })
      .def_readonly("stats", &EvalResult::stats)
      .def_readonly("translation_stats", &EvalResult::translation_stats)
      .def_readonly("rotation_stats", &EvalResult::rotation_stats)
      .def_property_readonly("rmse", [](const EvalResult& r) { return r.stats.rmse; })
      .def_property_readonly("mean", [](const EvalResult& r) { return r.stats.mean; })
      .def_property_readonly("median", [](const EvalResult& r) { return r.stats.median; })
      .def_property_readonly("std", [](const EvalResult& r) { return r.stats.std; })
      .def_property_readonly("min", [](const EvalResult& r) { return r.stats.min; })
      .def_property_readonly("max", [](const EvalResult& r) { return r.stats.max; })
      .def_property_readonly("sse", [](const EvalResult& r) { return r.stats.sse; })
      .def_property_readonly("title", [](const EvalResult& r) { return eval_title(r.options); })
      .def(
          "to_dict",
          [](const EvalResult& r, const std::string& label, const std::string& est_path, const std::string& ref_path) {
            nlohmann::json j = eval_result_to_json(r, run_source(r, label, est_path, ref_path));
            j["slamkit_version"] = SLAMKIT_VERSION;
            return json_to_python(j);
          },
          py::arg("label") = "", py::arg("est_path") = "", py::arg("ref_path") = "",
          "The run document of `slamkit eval --json` (input of render_html_report).")
      .def(
          "plot",
          [](const EvalResult& r, const py::object& path, const std::string& label) {
            const std::string source = path.is_none() ? "<plot>" : path.cast<std::string>();
            const nlohmann::json j = eval_result_to_json(r, run_source(r, label, "", ""));
            const EvalRunData data = eval_run_from_json(j, source);
            const std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + eval_figure(data).str();
            if (!path.is_none()) {
              std::ofstream out(source, std::ios::binary);
              if (!out) throw InputError(source, 0, "", "cannot write the plot");
              out << svg;
              if (!out) throw InputError(source, 0, "", "error while writing the plot");
            }
            return svg;
          },
          py::arg("path") = py::none(), py::arg("label") = "",
          "The `slamkit eval --plot` SVG figure as text (also written to path if given).")
      .def("__repr__", [](const EvalResult& r) {
        return "EvalResult('" + eval_title(r.options) + "', rmse=" + std::to_string(r.stats.rmse) + ")";
      });

  m.def("evaluate", &run_evaluate, py::arg("est"), py::arg("ref"), py::arg("metric") = "ate",
        py::arg("align") = py::none(), py::arg("relation") = "trans_part", py::arg("max_diff") = 0.01,
        py::arg("offset") = 0.0, py::arg("n_align") = 0, py::arg("delta") = 1.0, py::arg("delta_unit") = "f",
        py::arg("all_pairs") = false, py::arg("delta_tol") = 0.1, py::arg("pairs_from_reference") = false,
        "`slamkit eval ate|rpe` (evo_ape / evo_rpe): associate, align (default 'se3' for ATE, 'none' for RPE), "
        "errors and statistics.");
  m.def(
      "ate",
      [](const Trajectory& est, const Trajectory& ref, const py::object& align, const std::string& relation,
         double max_diff, double offset, std::size_t n_align) {
        return run_evaluate(est, ref, "ate", align, relation, max_diff, offset, n_align, 1.0, "f", false, 0.1, false);
      },
      py::arg("est"), py::arg("ref"), py::arg("align") = "se3", py::arg("relation") = "trans_part",
      py::arg("max_diff") = 0.01, py::arg("offset") = 0.0, py::arg("n_align") = 0, "evaluate(metric='ate', ...).");
  m.def(
      "rpe",
      [](const Trajectory& est, const Trajectory& ref, const py::object& align, const std::string& relation,
         double max_diff, double offset, std::size_t n_align, double delta, const std::string& unit, bool all_pairs,
         double tol, bool from_ref) {
        return run_evaluate(est, ref, "rpe", align, relation, max_diff, offset, n_align, delta, unit, all_pairs, tol,
                            from_ref);
      },
      py::arg("est"), py::arg("ref"), py::arg("align") = "none", py::arg("relation") = "trans_part",
      py::arg("max_diff") = 0.01, py::arg("offset") = 0.0, py::arg("n_align") = 0, py::arg("delta") = 1.0,
      py::arg("delta_unit") = "f", py::arg("all_pairs") = false, py::arg("delta_tol") = 0.1,
      py::arg("pairs_from_reference") = false, "evaluate(metric='rpe', ...).");

  m.def(
      "plot_trajectories",
      [](const py::list& runs, const std::string& view, double width, double height) {
        check_size(width, height);
        if (view != "top" && view != "side") throw py::value_error("view: 'top' or 'side'");
        const auto d = run_data(runs);
        return plot_trajectories(pointers(d), view == "top" ? TrajectoryView::kTop : TrajectoryView::kSide, width,
                                 height)
            .str();
      },
      py::arg("runs"), py::arg("view") = "top", py::arg("width") = 640.0, py::arg("height") = 480.0,
      "SVG of the estimates over the reference (top or side view). runs: EvalResult objects or run dicts.");
  m.def(
      "plot_error_over_time",
      [](const py::list& runs, double width, double height) {
        check_size(width, height);
        const auto d = run_data(runs);
        return plot_error_over_time(pointers(d), width, height).str();
      },
      py::arg("runs"), py::arg("width") = 640.0, py::arg("height") = 360.0,
      "SVG of the per-pair errors against time (one run: with rmse, mean, median and the std band).");
  m.def(
      "plot_error_along_path",
      [](const py::object& run, double width, double height) {
        check_size(width, height);
        py::list l;
        l.append(run);
        const auto d = run_data(l);
        return plot_error_along_path(d[0], width, height).str();
      },
      py::arg("run"), py::arg("width") = 640.0, py::arg("height") = 480.0,
      "SVG of the estimate coloured by its error over the reference.");
  m.def(
      "plot_error_histogram",
      [](const py::list& runs, double width, double height) {
        check_size(width, height);
        const auto d = run_data(runs);
        return plot_error_histogram(pointers(d), width, height).str();
      },
      py::arg("runs"), py::arg("width") = 640.0, py::arg("height") = 360.0, "SVG histogram of the errors.");

  m.def(
      "render_html_report",
      [](const py::list& runs, const std::string& title, const py::object& output) {
        std::vector<ReportInput> inputs;
        std::size_t k = 0;
        for (py::handle run : runs) {
          ReportInput in;
          if (py::isinstance<py::str>(run)) {
            in.path = run.cast<std::string>();
            std::ifstream f(in.path);
            if (!f) throw InputError(in.path, 0, "", "cannot open file");
            try {
              in.document = nlohmann::json::parse(f);
            } catch (const nlohmann::json::parse_error& e) {
              throw InputError(in.path, 0, "", std::string("not valid JSON: ") + e.what());
            }
          } else {
            in.path = "runs[" + std::to_string(k) + "]";
            in.document = python_to_json(run, in.path);
          }
          inputs.push_back(std::move(in));
          ++k;
        }
        ReportOptions o;
        o.title = title;
        o.generator = std::string("slamkit ") + SLAMKIT_VERSION + " (Python)";
        const std::string html = render_html_report(inputs, o);
        if (!output.is_none()) {
          const std::string path = output.cast<std::string>();
          std::ofstream out(path, std::ios::binary);
          if (!out) throw InputError(path, 0, "", "cannot write the report");
          out << html;
          if (!out) throw InputError(path, 0, "", "error while writing the report");
        }
        return html;
      },
      py::arg("runs"), py::arg("title") = "slamkit evaluation report", py::arg("output") = py::none(),
      "`slamkit report`: one HTML page from run documents (dicts such as EvalResult.to_dict() or "
      "optimize_pose_graph(as_dict=True), or paths of JSON files). Written to output if given.");
}

}  // namespace slamkit::python
