#include "slamkit/core/pose_graph.h"

#include <algorithm>
#include <deque>
#include <numeric>

#include "slamkit/core/error.h"

namespace slamkit {

const char* to_string(VertexKind kind) {
  switch (kind) {
    case VertexKind::kPose2: return "pose2";
    case VertexKind::kPose3: return "pose3";
    case VertexKind::kPoint2: return "point2";
    case VertexKind::kPoint3: return "point3";
  }
  return "?";
}

const char* to_string(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kPose2Pose2: return "pose2-pose2";
    case EdgeKind::kPose3Pose3: return "pose3-pose3";
    case EdgeKind::kPose2Point2: return "pose2-point2";
    case EdgeKind::kPose3Point3: return "pose3-point3";
  }
  return "?";
}

int tangent_dim(VertexKind kind) {
  switch (kind) {
    case VertexKind::kPose2: return 3;
    case VertexKind::kPose3: return 6;
    case VertexKind::kPoint2: return 2;
    case VertexKind::kPoint3: return 3;
  }
  return 0;
}

int error_dim(EdgeKind kind) {
  switch (kind) {
    case EdgeKind::kPose2Pose2: return 3;
    case EdgeKind::kPose3Pose3: return 6;
    case EdgeKind::kPose2Point2: return 2;
    case EdgeKind::kPose3Point3: return 3;
  }
  return 0;
}

bool PoseGraph::add_vertex(const GraphVertex& v) {
  if (!index_.emplace(v.id, vertices_.size()).second) return false;
  vertices_.push_back(v);
  return true;
}

void PoseGraph::remove_vertices(const std::vector<std::int64_t>& ids) {
  if (ids.empty()) return;
  std::vector<GraphVertex> kept;
  kept.reserve(vertices_.size());
  for (const GraphVertex& v : vertices_)
    if (std::find(ids.begin(), ids.end(), v.id) == ids.end()) kept.push_back(v);
  vertices_ = std::move(kept);
  index_.clear();
  for (std::size_t i = 0; i < vertices_.size(); ++i) index_.emplace(vertices_[i].id, i);
}

std::optional<std::size_t> PoseGraph::index_of(std::int64_t id) const {
  const auto it = index_.find(id);
  if (it == index_.end()) return std::nullopt;
  return it->second;
}

const GraphVertex& PoseGraph::vertex(std::int64_t id) const {
  const auto i = index_of(id);
  if (!i) throw InputError(source, 0, "id", "no vertex with id " + std::to_string(id));
  return vertices_[*i];
}

int PoseGraph::dimension() const {
  bool has2 = false, has3 = false;
  for (const auto& v : vertices_) {
    has2 |= v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPoint2;
    has3 |= v.kind == VertexKind::kPose3 || v.kind == VertexKind::kPoint3;
  }
  if (has2 && has3) throw InputError(source, 0, "", "graph mixes 2D and 3D vertices");
  return has3 ? 3 : has2 ? 2 : 0;
}

std::size_t PoseGraph::num_poses() const {
  return std::count_if(vertices_.begin(), vertices_.end(), [](const GraphVertex& v) {
    return v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPose3;
  });
}

std::size_t PoseGraph::num_points() const { return vertices_.size() - num_poses(); }

bool is_odometry(const GraphEdge& e) {
  const bool pose_pose = e.kind == EdgeKind::kPose2Pose2 || e.kind == EdgeKind::kPose3Pose3;
  return pose_pose && (e.to - e.from == 1 || e.from - e.to == 1);
}

namespace {

struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

// Sets the estimate of `target` from the known vertex `known` through edge e.
void propagate(const PoseGraph& g, const GraphEdge& e, const GraphVertex& known, GraphVertex& target) {
  const bool forward = e.from == known.id;  // known is the frame the measurement is in
  switch (e.kind) {
    case EdgeKind::kPose2Pose2:
      target.pose2 = forward ? known.pose2 * e.pose2 : known.pose2 * e.pose2.inverse();
      break;
    case EdgeKind::kPose3Pose3:
      target.pose3 = forward ? known.pose3 * e.pose3 : known.pose3 * e.pose3.inverse();
      break;
    case EdgeKind::kPose2Point2:
      target.point.head<2>() = known.pose2.act(e.point.head<2>());
      target.point.z() = 0.0;
      break;
    case EdgeKind::kPose3Point3: {
      SE3 sensor = known.pose3;
      const auto it = g.sensor_offsets.find(e.sensor_offset_id);
      if (it != g.sensor_offsets.end()) sensor = sensor * it->second;
      target.point = sensor.act(e.point);
      break;
    }
  }
  target.has_estimate = true;
}

bool can_propagate(const GraphEdge& e, const GraphVertex& known) {
  // Landmarks never act as a frame: a point edge propagates only from its pose.
  const bool point_edge = e.kind == EdgeKind::kPose2Point2 || e.kind == EdgeKind::kPose3Point3;
  return !point_edge || e.from == known.id;
}

}  // namespace

std::size_t count_connected_components(const PoseGraph& g) {
  const auto& vs = g.vertices();
  UnionFind uf(vs.size());
  auto join = [&](std::int64_t a, std::int64_t b) {
    const auto ia = g.index_of(a), ib = g.index_of(b);
    if (ia && ib) uf.unite(*ia, *ib);
  };
  for (const auto& e : g.edges) join(e.from, e.to);
  for (const auto& [a, b] : g.equivalences) join(a, b);
  std::size_t n = 0;
  for (std::size_t i = 0; i < vs.size(); ++i) n += uf.find(i) == i;
  return n;
}

Trajectory to_trajectory(const PoseGraph& g) {
  std::vector<const GraphVertex*> poses;
  for (const GraphVertex& v : g.vertices())
    if (v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPose3) poses.push_back(&v);
  std::sort(poses.begin(), poses.end(), [](const GraphVertex* a, const GraphVertex* b) { return a->id < b->id; });
  Trajectory t;
  for (const GraphVertex* v : poses) {
    const SE3 pose = v->kind == VertexKind::kPose3
                         ? v->pose3
                         : SE3(SO3::exp(Eigen::Vector3d(0, 0, v->pose2.theta())),
                               Eigen::Vector3d(v->pose2.x(), v->pose2.y(), 0.0));
    t.push_back(static_cast<double>(v->id), pose);
  }
  return t;
}

std::vector<std::int64_t> gauge_vertices(const PoseGraph& g, std::vector<std::string>* notes) {
  const auto& vs = g.vertices();
  UnionFind uf(vs.size());
  for (const auto& e : g.edges) {
    const auto a = g.index_of(e.from), b = g.index_of(e.to);
    if (a && b) uf.unite(*a, *b);
  }
  std::vector<std::int64_t> gauge;
  std::vector<char> component_fixed(vs.size(), 0);
  for (std::int64_t id : g.fixed) {
    const auto i = g.index_of(id);
    if (!i) throw InputError(g.source, 0, "FIX", "FIX names unknown vertex " + std::to_string(id));
    gauge.push_back(id);
    component_fixed[uf.find(*i)] = 1;
  }
  // Smallest pose id of each component without a fixed vertex.
  std::vector<std::ptrdiff_t> smallest(vs.size(), -1);
  for (std::size_t i = 0; i < vs.size(); ++i) {
    if (vs[i].kind != VertexKind::kPose2 && vs[i].kind != VertexKind::kPose3) continue;
    const std::size_t r = uf.find(i);
    if (smallest[r] < 0 || vs[i].id < vs[smallest[r]].id) smallest[r] = static_cast<std::ptrdiff_t>(i);
  }
  std::size_t components = 0, added = 0;
  for (std::size_t r = 0; r < vs.size(); ++r) {
    if (uf.find(r) != r) continue;
    ++components;
    if (component_fixed[r] || smallest[r] < 0) continue;
    gauge.push_back(vs[smallest[r]].id);
    ++added;
  }
  if (notes && added > 0) {
    if (components > 1) {
      notes->push_back("graph has " + std::to_string(components) +
                       " disconnected components: the gauge is fixed in each one separately (" + std::to_string(added) +
                       " vertices fixed); their relative placement is arbitrary");
    } else if (g.fixed.empty()) {
      notes->push_back("no FIX vertex: vertex " + std::to_string(gauge.back()) + " is held fixed (gauge)");
    }
  }
  return gauge;
}

std::size_t complete_estimates_by_odometry(PoseGraph& g) {
  const std::size_t n = g.vertices().size();
  std::vector<std::vector<std::size_t>> incident(n);
  for (std::size_t k = 0; k < g.edges.size(); ++k) {
    const auto a = g.index_of(g.edges[k].from), b = g.index_of(g.edges[k].to);
    if (!a || !b) throw InputError(g.source, g.edges[k].line, "id", "edge names an unknown vertex");
    incident[*a].push_back(k);
    incident[*b].push_back(k);
  }
  std::vector<std::size_t> order(n);  // vertex indices by id
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return g.vertices()[a].id < g.vertices()[b].id; });

  std::size_t initialized = 0;
  auto other_end = [&](const GraphEdge& e, std::size_t from_index) {
    return *g.index_of(e.from == g.vertices()[from_index].id ? e.to : e.from);
  };
  while (true) {
    // 1. Walk the odometry chain in id order from every vertex that has an estimate.
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const std::size_t a = order[k], b = order[k + 1];
      const GraphVertex& va = g.vertices()[a];
      GraphVertex& vb = g.vertex_at(b);
      if (!va.has_estimate || vb.has_estimate || vb.id != va.id + 1) continue;
      for (std::size_t ei : incident[a]) {
        const GraphEdge& e = g.edges[ei];
        if (is_odometry(e) && other_end(e, a) == b) {
          propagate(g, e, va, vb);
          ++initialized;
          break;
        }
      }
    }
    // 2. Breadth-first over all edges from everything known.
    std::deque<std::size_t> queue;
    for (std::size_t i = 0; i < n; ++i)
      if (g.vertices()[i].has_estimate) queue.push_back(i);
    while (!queue.empty()) {
      const std::size_t a = queue.front();
      queue.pop_front();
      for (std::size_t ei : incident[a]) {
        const GraphEdge& e = g.edges[ei];
        const std::size_t b = other_end(e, a);
        if (g.vertices()[b].has_estimate || !can_propagate(e, g.vertices()[a])) continue;
        propagate(g, e, g.vertices()[a], g.vertex_at(b));
        ++initialized;
        queue.push_back(b);
      }
    }
    // 3. A component with no estimate at all: root it at its smallest pose id.
    const auto root = std::find_if(order.begin(), order.end(), [&](std::size_t i) {
      const GraphVertex& v = g.vertices()[i];
      return !v.has_estimate && (v.kind == VertexKind::kPose2 || v.kind == VertexKind::kPose3);
    });
    if (root == order.end()) break;
    GraphVertex& r = g.vertex_at(*root);
    r.pose2 = SE2();
    r.pose3 = SE3();
    r.has_estimate = true;
    ++initialized;
  }
  return initialized;
}

}  // namespace slamkit
