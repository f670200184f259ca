// Bindings of the data types of slamkit/core that files describe: PoseGraph (vertices,
// edges, information matrices, chi2) and Trajectory (stamped SE(3) poses), with NumPy
// arrays in and out. Part of the core module's bindings (split for compile time).
#include <sstream>

#include "bind_common.h"
#include "slamkit/core/information.h"
#include "slamkit/core/manifold.h"
#include "slamkit/core/pose_graph.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/core/trajectory.h"

namespace slamkit::python {
namespace {

py::object vertex_estimate(const GraphVertex& v) {
  switch (v.kind) {
    case VertexKind::kPose2: return py::cast(v.pose2);
    case VertexKind::kPose3: return py::cast(v.pose3);
    case VertexKind::kPoint2: return py::cast(Eigen::Vector2d(v.point.head<2>()));
    case VertexKind::kPoint3: return py::cast(Eigen::Vector3d(v.point));
  }
  return py::none();
}

py::object edge_measurement(const GraphEdge& e) {
  switch (e.kind) {
    case EdgeKind::kPose2Pose2: return py::cast(e.pose2);
    case EdgeKind::kPose3Pose3: return py::cast(e.pose3);
    case EdgeKind::kPose2Point2: return py::cast(Eigen::Vector2d(e.point.head<2>()));
    case EdgeKind::kPose3Point3: return py::cast(Eigen::Vector3d(e.point));
  }
  return py::none();
}

const GraphEdge& edge_at(const PoseGraph& g, std::ptrdiff_t i) {
  const auto n = static_cast<std::ptrdiff_t>(g.edges.size());
  if (i < 0) i += n;
  if (i < 0 || i >= n) throw py::index_error("edge index out of range");
  return g.edges[static_cast<std::size_t>(i)];
}

void add_edge(PoseGraph& g, std::int64_t from, std::int64_t to, const py::handle& z, const py::handle& info) {
  const GraphVertex& a = g.vertex(from);
  const GraphVertex& b = g.vertex(to);
  GraphEdge e;
  e.from = from, e.to = to;
  const bool pose2 = a.kind == VertexKind::kPose2, pose3 = a.kind == VertexKind::kPose3;
  const bool point = b.kind == VertexKind::kPoint2 || b.kind == VertexKind::kPoint3;
  if (!point && !py::isinstance<SE2>(z) && !py::isinstance<SE3>(z))
    throw py::value_error("add_edge: a pose-pose measurement must be an SE2 or SE3");
  if (pose2 && b.kind == VertexKind::kPose2) {
    if (!py::isinstance<SE2>(z)) throw py::value_error("add_edge: 2D poses need an SE2 measurement");
    e.kind = EdgeKind::kPose2Pose2, e.pose2 = z.cast<SE2>();
  } else if (pose3 && b.kind == VertexKind::kPose3) {
    if (!py::isinstance<SE3>(z)) throw py::value_error("add_edge: 3D poses need an SE3 measurement");
    e.kind = EdgeKind::kPose3Pose3, e.pose3 = z.cast<SE3>();
  } else if (pose2 && b.kind == VertexKind::kPoint2) {
    e.kind = EdgeKind::kPose2Point2, e.point << to_vector(z, 2, "measured"), 0.0;
  } else if (pose3 && b.kind == VertexKind::kPoint3) {
    e.kind = EdgeKind::kPose3Point3, e.point = to_vector(z, 3, "measured");
  } else {
    throw py::value_error("add_edge: no edge type from a " + std::string(to_string(a.kind)) + " to a " +
                          to_string(b.kind));
  }
  const int d = error_dim(e.kind);
  e.information = to_matrix(info, d, d, "information");
  g.edges.push_back(std::move(e));
}

// Pose estimates in vertex order: N×3 [x, y, theta] (2D) or N×7 [t, qx, qy, qz, qw] (3D).
py::array_t<double> poses_array(const PoseGraph& g) {
  const int dim = g.dimension();
  const int cols = dim == 3 ? 7 : 3;
  std::vector<const GraphVertex*> poses;
  for (const GraphVertex& v : g.vertices())
    if (v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPose3) poses.push_back(&v);
  py::array_t<double> a({static_cast<py::ssize_t>(poses.size()), static_cast<py::ssize_t>(cols)});
  for (std::size_t i = 0; i < poses.size(); ++i) {
    double* row = a.mutable_data(i, 0);
    if (dim == 3)
      ManifoldTraits<SE3>::to_params(poses[i]->pose3, row);
    else
      ManifoldTraits<SE2>::to_params(poses[i]->pose2, row);
  }
  return a;
}

void set_poses(PoseGraph& g, const py::handle& arr) {
  const int dim = g.dimension();
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < g.vertices().size(); ++i)
    if (g.vertices()[i].kind == VertexKind::kPose2 || g.vertices()[i].kind == VertexKind::kPose3) idx.push_back(i);
  const RowMatrixXd P = to_matrix(arr, static_cast<Eigen::Index>(idx.size()), dim == 3 ? 7 : 3, "poses");
  for (std::size_t k = 0; k < idx.size(); ++k) {
    GraphVertex& v = g.vertex_at(idx[k]);
    if (dim == 3) {
      if (P.row(k).tail<4>().norm() < 1e-12) throw py::value_error("poses: zero quaternion in row " + std::to_string(k));
      v.pose3 = ManifoldTraits<SE3>::from_params(P.row(k).data());
    } else {
      v.pose2 = ManifoldTraits<SE2>::from_params(P.row(k).data());
    }
    v.has_estimate = true;
  }
}

Trajectory trajectory_from_arrays(const py::handle& stamps, const py::handle& positions, const py::object& quats,
                                  const py::object& rotations, bool has_timestamps) {
  const Eigen::VectorXd t = to_vector(stamps, -1, "stamps");
  const RowMatrixXd p = to_matrix(positions, t.size(), 3, "positions");
  if (!quats.is_none() && !rotations.is_none()) throw py::value_error("give quaternions or rotations, not both");
  RowMatrixXd q;
  std::vector<Eigen::Matrix3d> R;
  if (!quats.is_none()) q = to_matrix(quats, t.size(), 4, "quaternions");
  if (!rotations.is_none()) {
    const auto a = py::array_t<double, py::array::forcecast>::ensure(rotations);
    if (!a || a.ndim() != 3 || a.shape(0) != t.size() || a.shape(1) != 3 || a.shape(2) != 3)
      throw py::value_error("rotations: expected shape (N, 3, 3) with N = len(stamps)");
    const auto u = a.unchecked<3>();
    for (Eigen::Index k = 0; k < t.size(); ++k) {
      Eigen::Matrix3d M;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) M(i, j) = u(k, i, j);
      require_finite(M, "rotations");
      // As the KITTI reader: a matrix far from orthonormal is an error, not a rotation.
      if ((M.transpose() * M - Eigen::Matrix3d::Identity()).norm() > 1e-2 || M.determinant() <= 0.0)
        throw py::value_error("rotations: matrix " + std::to_string(k) + " is not a rotation");
      R.push_back(M);
    }
  }
  Trajectory traj;
  traj.reserve(static_cast<std::size_t>(t.size()));
  traj.set_has_timestamps(has_timestamps);
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    TrajectorySample s;
    s.stamp = t(k);
    SO3 rot;
    if (q.size()) {
      if (q.row(k).norm() < 1e-12) throw py::value_error("quaternions: zero quaternion in row " + std::to_string(k));
      rot = SO3(Eigen::Quaterniond(q(k, 3), q(k, 0), q(k, 1), q(k, 2)));
    } else if (!R.empty()) {
      rot = SO3::from_matrix(R[k]);
      s.source_rotation = R[k];
    }
    s.T_world_body = SE3(rot, p.row(k).transpose());
    if (!traj.empty() && s.stamp < traj[traj.size() - 1].stamp)
      throw py::value_error("stamps must be non-decreasing (row " + std::to_string(k) + ")");
    traj.push_back(std::move(s));
  }
  return traj;
}

template <class F>
py::array_t<double> per_sample(const Trajectory& t, std::vector<py::ssize_t> tail, F&& fill) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(t.size())};
  py::ssize_t stride = 1;
  for (py::ssize_t d : tail) shape.push_back(d), stride *= d;
  py::array_t<double> a(shape);
  double* out = a.mutable_data();
  for (std::size_t i = 0; i < t.size(); ++i) fill(t[i], out + i * stride);
  return a;
}

}  // namespace

void init_pose_graph(py::module_& m) {
  py::class_<GraphVertex>(m, "GraphVertex", "A vertex of a pose graph with its estimate.")
      .def_readonly("id", &GraphVertex::id)
      .def_property_readonly("kind", [](const GraphVertex& v) { return std::string(to_string(v.kind)); })
      .def_property_readonly("estimate", &vertex_estimate, "SE2, SE3, or a point array.")
      .def_readonly("has_estimate", &GraphVertex::has_estimate)
      .def_readonly("line", &GraphVertex::line, "Source line (0 if not from a file).");
  py::class_<GraphEdge>(m, "GraphEdge", "An edge: measurement of `to` in the frame of `from`, with information.")
      .def_readonly("from_id", &GraphEdge::from)
      .def_readonly("to_id", &GraphEdge::to)
      .def_property_readonly("kind", [](const GraphEdge& e) { return std::string(to_string(e.kind)); })
      .def_property_readonly("measured", &edge_measurement)
      .def_readonly("information", &GraphEdge::information, "In g2o's error coordinates.")
      .def_readonly("line", &GraphEdge::line);
  py::class_<InformationHealth>(m, "InformationHealth", "Counts of the information matrices of a graph by health.")
      .def_readonly("positive_definite", &InformationHealth::positive_definite)
      .def_readonly("singular", &InformationHealth::singular)
      .def_readonly("indefinite", &InformationHealth::indefinite)
      .def_readonly("not_symmetric", &InformationHealth::not_symmetric)
      .def_readonly("not_finite", &InformationHealth::not_finite)
      .def_readonly("first_bad_line", &InformationHealth::first_bad_line)
      .def("bad", &InformationHealth::bad, "Matrices that are not positive definite.");

  py::class_<PoseGraph>(m, "PoseGraph",
                        "A pose-graph dataset: 2D/3D pose and landmark vertices with estimates, edges with "
                        "measurements and information matrices (g2o conventions, docs/formats.md).")
      .def(py::init<>())
      .def_readwrite("source", &PoseGraph::source)
      .def_readwrite("format", &PoseGraph::format)
      .def_readwrite("fixed", &PoseGraph::fixed, "FIX vertex ids (gauge).")
      .def(
          "add_pose",
          [](PoseGraph& g, std::int64_t id, const py::handle& pose) {
            GraphVertex v;
            v.id = id;
            if (py::isinstance<SE2>(pose)) {
              v.kind = VertexKind::kPose2, v.pose2 = pose.cast<SE2>();
            } else if (py::isinstance<SE3>(pose)) {
              v.kind = VertexKind::kPose3, v.pose3 = pose.cast<SE3>();
            } else {
              throw py::value_error("add_pose: expected an SE2 or SE3");
            }
            if (!g.add_vertex(v)) throw py::value_error("add_pose: vertex " + std::to_string(id) + " exists already");
          },
          py::arg("id"), py::arg("pose"), "Adds a 2D (SE2) or 3D (SE3) pose vertex.")
      .def(
          "add_point",
          [](PoseGraph& g, std::int64_t id, const py::handle& p) {
            const Eigen::VectorXd x = to_vector(p, -1, "point");
            if (x.size() != 2 && x.size() != 3) throw py::value_error("add_point: expected a 2- or 3-vector");
            GraphVertex v;
            v.id = id;
            v.kind = x.size() == 2 ? VertexKind::kPoint2 : VertexKind::kPoint3;
            v.point.head(x.size()) = x;
            if (!g.add_vertex(v)) throw py::value_error("add_point: vertex " + std::to_string(id) + " exists already");
          },
          py::arg("id"), py::arg("point"), "Adds a 2D or 3D landmark vertex.")
      .def("add_edge", &add_edge, py::arg("from_id"), py::arg("to_id"), py::arg("measured"), py::arg("information"),
           "Adds an edge; its kind follows the vertex kinds (pose-pose: SE2/SE3, pose-point: a vector).")
      .def_property_readonly("num_vertices", [](const PoseGraph& g) { return g.vertices().size(); })
      .def_property_readonly("num_edges", [](const PoseGraph& g) { return g.edges.size(); })
      .def("dimension", &PoseGraph::dimension, "2 or 3 (0: empty).")
      .def("num_poses", &PoseGraph::num_poses, "Number of pose vertices.")
      .def("num_points", &PoseGraph::num_points, "Number of landmark vertices.")
      .def("vertex", &PoseGraph::vertex, py::arg("id"), "The vertex with this id (InputError if unknown).")
      .def("has_vertex", [](const PoseGraph& g, std::int64_t id) { return g.index_of(id).has_value(); },
           py::arg("id"), "True if a vertex has this id.")
      .def("edge", &edge_at, py::arg("index"), "Edge i (negative: from the end) as a GraphEdge copy.")
      .def(
          "vertex_ids",
          [](const PoseGraph& g) {
            std::vector<std::int64_t> ids;
            for (const auto& v : g.vertices()) ids.push_back(v.id);
            return to_array(ids);
          },
          "All vertex ids in storage order.")
      .def(
          "pose_ids",
          [](const PoseGraph& g) {
            std::vector<std::int64_t> ids;
            for (const auto& v : g.vertices())
              if (v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPose3) ids.push_back(v.id);
            return to_array(ids);
          },
          "Ids of the pose vertices, in the row order of poses().")
      .def("poses", &poses_array, "Pose estimates: N×3 [x, y, theta] (2D) or N×7 [tx, ty, tz, qx, qy, qz, qw] (3D).")
      .def("set_poses", &set_poses, py::arg("poses"), "Replaces the pose estimates (same layout as poses()).")
      .def(
          "points",
          [](const PoseGraph& g) {
            std::vector<Eigen::Vector3d> p;
            for (const auto& v : g.vertices())
              if (v.kind == VertexKind::kPoint2 || v.kind == VertexKind::kPoint3) p.push_back(v.point);
            return to_array(p);
          },
          "Landmark estimates, N×3 (z = 0 in 2D).")
      .def(
          "edge_ids",
          [](const PoseGraph& g) {
            py::array_t<std::int64_t> a({static_cast<py::ssize_t>(g.edges.size()), py::ssize_t{2}});
            auto u = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < g.edges.size(); ++i) u(i, 0) = g.edges[i].from, u(i, 1) = g.edges[i].to;
            return a;
          },
          "M×2 int64 [from, to] of every edge.")
      .def(
          "edge_chi2",
          [](const PoseGraph& g) {
            std::vector<double> c;
            for (const auto& e : g.edges) c.push_back(edge_chi2(g, e));
            return to_array(c);
          },
          "e^T Omega e of every edge (array).")
      .def("edge_error", [](const PoseGraph& g, std::ptrdiff_t i) { return edge_error(g, edge_at(g, i)); },
           py::arg("index"), "g2o error vector of edge i at the current estimates.")
      .def("total_chi2", &total_chi2, "Sum of e^T Omega e over all edges (g2o's chi2).")
      .def("count_connected_components", &count_connected_components, "Connected components (EQUIV joins too).")
      .def(
          "gauge_vertices",
          [](const PoseGraph& g) {
            std::vector<std::string> notes;
            auto ids = gauge_vertices(g, &notes);
            return py::make_tuple(ids, notes);
          },
          "(ids, notes): the vertices held fixed (FIX, else the smallest pose id per component).")
      .def("check_information", [](const PoseGraph& g) { return check_information(g); }, "Health of every information matrix.")
      .def("repair_information", &repair_information, py::arg("relative_floor") = 1e-9,
           "Projects non-PD information matrices to the PSD cone; returns how many changed.")
      .def("complete_estimates_by_odometry", &complete_estimates_by_odometry,
           "Gives vertices without an estimate one by composing measurements; returns how many.")
      .def("to_trajectory", &to_trajectory, "Poses in id order (id as stamp; 2D poses in the z = 0 plane).")
      .def("copy", [](const PoseGraph& g) { return PoseGraph(g); }, "An independent copy.")
      .def("__copy__", [](const PoseGraph& g) { return PoseGraph(g); })
      .def("__deepcopy__", [](const PoseGraph& g, py::dict) { return PoseGraph(g); })
      .def("__repr__", [](const PoseGraph& g) {
        std::ostringstream os;
        os << "PoseGraph('" << g.source << "', " << g.vertices().size() << " vertices, " << g.edges.size()
           << " edges)";
        return os.str();
      });

  py::class_<Trajectory>(m, "Trajectory",
                         "Time-ordered body poses T_world_body with stamps in seconds (KITTI: indices, "
                         "has_timestamps False).")
      .def(py::init<>())
      .def_static("from_arrays", &trajectory_from_arrays, py::arg("stamps"), py::arg("positions"),
                  py::arg("quaternions") = py::none(), py::arg("rotations") = py::none(),
                  py::arg("has_timestamps") = true,
                  "From stamps (N,), positions (N,3) and quaternions (N,4) [qx, qy, qz, qw] or rotation "
                  "matrices (N,3,3) (kept as given for the metrics, like KITTI files).")
      .def(
          "append",
          [](Trajectory& t, double stamp, const SE3& pose) {
            require_finite(stamp, "stamp");
            t.push_back(stamp, pose);
          },
          py::arg("stamp"), py::arg("pose"), "Appends a sample (stamps must not go back in time).")
      .def("__len__", &Trajectory::size)
      .def("size", &Trajectory::size, "Number of samples.")
      .def(
          "pose",
          [](const Trajectory& t, std::ptrdiff_t i) {
            const auto n = static_cast<std::ptrdiff_t>(t.size());
            if (i < 0) i += n;
            if (i < 0 || i >= n) throw py::index_error("sample index out of range");
            return t[static_cast<std::size_t>(i)].T_world_body;
          },
          py::arg("index"), "The pose T_world_body of sample i (negative: from the end).")
      .def("stamps", [](const Trajectory& t) { return to_array(t.stamps()); }, "Stamps (N,) [s].")
      .def("positions", [](const Trajectory& t) { return to_array(t.positions()); }, "Positions (N, 3).")
      .def(
          "quaternions",
          [](const Trajectory& t) {
            return per_sample(t, {4}, [](const TrajectorySample& s, double* o) {
              Eigen::Map<Eigen::Vector4d> out(o);
              out = s.T_world_body.rotation().quaternion().coeffs();
            });
          },
          "Orientations (N, 4) [qx, qy, qz, qw].")
      .def(
          "rotations",
          [](const Trajectory& t) {
            return per_sample(t, {3, 3}, [](const TrajectorySample& s, double* o) {
              Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> out(o);
              out = s.rotation_matrix();
            });
          },
          "Rotation matrices (N, 3, 3), as read from the file when it had matrices.")
      .def(
          "matrices",
          [](const Trajectory& t) {
            return per_sample(t, {4, 4}, [](const TrajectorySample& s, double* o) {
              Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> out(o);
              out = s.T_world_body.matrix();
            });
          },
          "Homogeneous matrices (N, 4, 4).")
      .def(
          "velocities",
          [](const Trajectory& t) -> py::object {
            if (!t.has_velocities()) return py::none();
            return per_sample(t, {3}, [](const TrajectorySample& s, double* o) {
              Eigen::Map<Eigen::Vector3d> out(o);
              out = *s.v_world;
            });
          },
          "World-frame velocities (N, 3), or None.")
      .def(
          "stamps_ns",
          [](const Trajectory& t) -> py::object {
            if (!t.has_stamps_ns()) return py::none();
            std::vector<std::int64_t> ns;
            for (const auto& s : t) ns.push_back(*s.stamp_ns);
            return to_array(ns);
          },
          "Exact integer stamps [ns] (int64), or None.")
      .def_property("has_timestamps", &Trajectory::has_timestamps, &Trajectory::set_has_timestamps)
      .def_readwrite("metadata", &Trajectory::metadata)
      .def("path_length", &Trajectory::path_length, "Arc length [m].")
      .def("duration", &Trajectory::duration, "Last stamp - first stamp [s].")
      .def(
          "subset",
          [](const Trajectory& t, const std::vector<std::size_t>& ids) {
            for (std::size_t i : ids)
              if (i >= t.size()) throw py::index_error("subset: index " + std::to_string(i) + " out of range");
            try {
              return t.subset(ids);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
          },
          py::arg("ids"), "The samples at ids, in that order.")
      .def("copy", [](const Trajectory& t) { return Trajectory(t); }, "An independent copy.")
      .def("__repr__", [](const Trajectory& t) {
        return "Trajectory(" + std::to_string(t.size()) + " poses" + (t.has_timestamps() ? "" : ", no timestamps") + ")";
      });
}

}  // namespace slamkit::python
