// Bindings of slamkit/sim: the synthetic pose-graph generators (manhattan 2D, sphere 3D) with
// known ground truth, and the "sim:NAME?key=value" specs the CLI accepts.
#include "bind_common.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit::python {

void init_sim(py::module_& m) {
  py::class_<PoseGraphSimOptions>(m, "PoseGraphSimOptions",
                                  "Generator options; every keyword defaults to the C++ default.")
      .def(py::init([](const py::kwargs& kw) {
        py::object tmp = py::cast(PoseGraphSimOptions{});
        set_from_kwargs(tmp, kw);
        return tmp.cast<PoseGraphSimOptions>();
      }))
      .def_readwrite("world", &PoseGraphSimOptions::world, "'manhattan' (2D) or 'sphere' (3D).")
      .def_readwrite("num_poses", &PoseGraphSimOptions::num_poses, "manhattan")
      .def_readwrite("turn_probability", &PoseGraphSimOptions::turn_probability, "manhattan")
      .def_readwrite("loop_radius", &PoseGraphSimOptions::loop_radius, "manhattan")
      .def_readwrite("loop_probability", &PoseGraphSimOptions::loop_probability, "manhattan")
      .def_readwrite("rings", &PoseGraphSimOptions::rings, "sphere")
      .def_readwrite("poses_per_ring", &PoseGraphSimOptions::poses_per_ring, "sphere")
      .def_readwrite("radius", &PoseGraphSimOptions::radius, "sphere")
      .def_readwrite("translation_sigma", &PoseGraphSimOptions::translation_sigma, "[m]")
      .def_readwrite("rotation_sigma", &PoseGraphSimOptions::rotation_sigma, "[rad]")
      .def_readwrite("seed", &PoseGraphSimOptions::seed)
      .def("__repr__", [](const py::object& self) {
        return repr_from_fields(self, "PoseGraphSimOptions",
                                {"world", "num_poses", "turn_probability", "loop_radius", "loop_probability", "rings",
                                 "poses_per_ring", "radius", "translation_sigma", "rotation_sigma", "seed"});
      });

  m.def(
      "generate_pose_graph",
      [](const py::object& options, bool ground_truth, const py::kwargs& kw) -> py::object {
        PoseGraphSimOptions o;
        if (!options.is_none()) {
          if (kw.size() > 0) throw py::type_error("generate_pose_graph: give options or keywords, not both");
          o = options.cast<PoseGraphSimOptions>();
        } else {
          py::object tmp = py::cast(PoseGraphSimOptions{});
          set_from_kwargs(tmp, kw);
          o = tmp.cast<PoseGraphSimOptions>();
        }
        for (double v : {o.turn_probability, o.loop_radius, o.loop_probability, o.radius, o.translation_sigma,
                         o.rotation_sigma})
          require_finite(v, "generate_pose_graph option");
        PoseGraph truth;
        PoseGraph g;
        {
          py::gil_scoped_release release;
          g = generate_pose_graph(o, ground_truth ? &truth : nullptr);
        }
        if (ground_truth) return py::make_tuple(std::move(g), std::move(truth));
        return py::cast(std::move(g));
      },
      py::arg("options") = py::none(), py::arg("ground_truth") = false,
      "A noisy synthetic pose graph (generate_pose_graph(world='sphere', rings=10)); with ground_truth=True "
      "returns (graph, truth), truth holding the true poses as estimates. Deterministic for a seed.");
  m.def(
      "parse_sim_spec",
      [](const std::string& spec) -> py::object {
        PoseGraphSimOptions o;
        if (!parse_sim_spec(spec, &o)) return py::none();
        return py::cast(o);
      },
      py::arg("spec"), "Options of 'sim:sphere?seed=3' and the like, or None if spec is not a sim: spec.");
}

}  // namespace slamkit::python
