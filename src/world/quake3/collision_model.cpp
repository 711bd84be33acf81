#include "valerant/world/quake3/collision_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "valerant/common/error.h"
#include "valerant/world/quake3/patch.h"

namespace valerant::quake3 {
namespace {

using Eigen::Vector3f;

// A box that penetrates a brush by less than this is only touching it, so a player
// resting exactly on a floor (or brushing a wall) is not in solid despite rounding.
constexpr float kTouchEpsilon = 0.01f;

// Lowest value of n.dot(x) over the box [mins, maxs] around the origin: the corner that
// meets the plane first (the game's per-signbits offset). Adding it to the plane
// test of the centre tests the whole box against the brush grown by the box.
float nearestCornerOffset(const Vector3f& n, const Vector3f& mins, const Vector3f& maxs) {
  float offset = 0;
  for (int a = 0; a < 3; ++a) offset += n[a] * (n[a] < 0 ? maxs[a] : mins[a]);
  return offset;
}

// 0..5 for normals -x, +x, -y, +y, -z, +z; -1 for any other normal.
int axialSide(const Eigen::Vector4f& plane) {
  for (int a = 0; a < 3; ++a)
    if (std::abs(plane[a]) > 0.99999f) return 2 * a + (plane[a] > 0 ? 1 : 0);
  return -1;
}

// Bounds of the convex polytope from every vertex (the intersection of three planes
// lying inside all others); empty when the planes enclose nothing.
Eigen::AlignedBox3f boundsByClipping(const std::vector<Eigen::Vector4f>& planes) {
  Eigen::AlignedBox3f bounds;
  const size_t n = planes.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      for (size_t k = j + 1; k < n; ++k) {
        Eigen::Matrix3d m;
        m << planes[i].head<3>().cast<double>().transpose(),
            planes[j].head<3>().cast<double>().transpose(),
            planes[k].head<3>().cast<double>().transpose();
        if (std::abs(m.determinant()) < 1e-9) continue;
        const Eigen::Vector3d p = m.inverse() * Eigen::Vector3d(planes[i][3], planes[j][3], planes[k][3]);
        const bool inside = std::all_of(planes.begin(), planes.end(), [&](const Eigen::Vector4f& q) {
          return q.head<3>().cast<double>().dot(p) <= q[3] + 0.01;
        });
        if (inside) bounds.extend(p.cast<float>());
      }
  return bounds;
}

// Sets the brush bounds from its planes and adds the axial bounding planes it lacks.
// Brushes compiled by q3map2 start with the six axial sides and carry bevel planes
// on their slanted edges, which keeps the plane-only box test exact; hand-made
// brushes get at least the axial ones. Returns false for an empty brush.
bool completeBrush(ConvexBrush& brush) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  Vector3f lo = Vector3f::Constant(-kInf), hi = Vector3f::Constant(kInf);
  bool has_side[6] = {};
  for (const auto& plane : brush.planes) {
    const int side = axialSide(plane);
    if (side < 0) continue;
    has_side[side] = true;
    const int a = side / 2;
    if (side % 2) hi[a] = std::min(hi[a], plane[3] / plane[a]);
    else lo[a] = std::max(lo[a], plane[3] / plane[a]);
  }
  const bool all_axial = std::all_of(std::begin(has_side), std::end(has_side), [](bool b) { return b; });
  brush.bounds = all_axial ? Eigen::AlignedBox3f(lo, hi) : boundsByClipping(brush.planes);
  if (brush.bounds.isEmpty()) return false;
  for (int side = 0; side < 6; ++side) {
    if (has_side[side]) continue;
    const int a = side / 2;
    Eigen::Vector4f plane = Eigen::Vector4f::Zero();
    plane[a] = side % 2 ? 1.f : -1.f;
    plane[3] = side % 2 ? brush.bounds.max()[a] : -brush.bounds.min()[a];
    brush.planes.push_back(plane);
  }
  return true;
}

// True when the box [center+mins, center+maxs] penetrates the brush. Only the
// brush planes separate, so without bevel planes a box near an edge of a slanted
// brush could be reported inside; q3map2's brushes carry those bevels.
bool boxOverlapsBrush(const ConvexBrush& brush, const Vector3f& center, const Vector3f& mins,
                      const Vector3f& maxs) {
  for (const auto& plane : brush.planes) {
    const Vector3f n = plane.head<3>();
    if (n.dot(center) + nearestCornerOffset(n, mins, maxs) - plane[3] > -kTouchEpsilon) return false;
  }
  return true;
}

// Fraction of the move start -> end at which the box first touches the brush (the
// game's CM_TraceThroughBrush against the brush grown by the box); nullopt when the
// move misses it. The overlap test treats the brush as shrunk by kTouchEpsilon so
// that grazing contact is no hit, but the reported fraction is that of exact contact.
std::optional<float> sweepFraction(const ConvexBrush& brush, const Vector3f& start,
                                   const Vector3f& end, const Vector3f& mins, const Vector3f& maxs) {
  float enter = 0, enter_exact = 0, leave = 1;
  for (const auto& plane : brush.planes) {
    const Vector3f n = plane.head<3>();
    const float offset = nearestCornerOffset(n, mins, maxs) - plane[3];
    const float d1 = n.dot(start) + offset, d2 = n.dot(end) + offset;
    const float e1 = d1 + kTouchEpsilon, e2 = d2 + kTouchEpsilon;
    if (e1 > 0 && e2 >= e1) return std::nullopt;  // stays in front of this side
    if (e1 <= 0 && e2 <= 0) continue;             // stays behind it
    const float f = e1 / (e1 - e2);
    if (e1 > e2) {
      if (f > enter) {
        enter = f;
        enter_exact = std::max(0.f, d1 / (d1 - d2));
      }
    } else {
      leave = std::min(leave, f);
    }
  }
  if (enter > 1 || enter >= leave) return std::nullopt;
  return enter_exact;
}

// Segments per Bezier block edge of a patch's collision surface. The game subdivides
// adaptively until the chords are within 16 units of the curve; a fixed fine level
// follows the drawn surface instead, which differs from the game's by at most that.
constexpr int kPatchCollisionLevel = 4;

// Zero-thickness brush of one patch triangle (the game's facets are thin too, and a
// box still collides with them). Its planes are all separating axes of box versus
// triangle: both faces, the three axial bevels pairs and every edge x axis bevel,
// so the plane-only tests are exact for it.
std::optional<ConvexBrush> facetBrush(const std::array<Vector3f, 3>& v, int contents) {
  Vector3f normal = (v[1] - v[0]).cross(v[2] - v[0]);
  if (normal.squaredNorm() < 1e-6f) return std::nullopt;
  normal.normalize();
  ConvexBrush brush;
  brush.contents = contents;
  auto addPlane = [&](const Vector3f& n) {
    float dist = -std::numeric_limits<float>::infinity();
    for (const Vector3f& p : v) dist = std::max(dist, n.dot(p));
    brush.planes.emplace_back(n.x(), n.y(), n.z(), dist);
  };
  addPlane(normal);
  addPlane(-normal);
  for (int a = 0; a < 3; ++a) {
    addPlane(-Vector3f::Unit(a));
    addPlane(Vector3f::Unit(a));
  }
  for (int e = 0; e < 3; ++e) {
    const Vector3f edge = v[(e + 1) % 3] - v[e];
    const Vector3f& opposite = v[(e + 2) % 3];
    for (int a = 0; a < 3; ++a) {
      Vector3f n = edge.cross(Vector3f::Unit(a));
      if (n.squaredNorm() < 1e-6f * edge.squaredNorm()) continue;  // edge along the axis
      n.normalize();
      const float edge_side = n.dot(v[e]) - n.dot(opposite);
      if (std::abs(edge_side) < 1e-4f) continue;  // n is the face normal: already added
      addPlane(edge_side > 0 ? n : Vector3f(-n));
    }
  }
  return brush;
}

// Facets of every solid Bezier patch of the world model: the game collides with
// patches (cm_patch.c), and some maps' floors are made of nothing else.
void addPatchFacets(const BspMap& map, int contents_mask, std::vector<ConvexBrush>& out) {
  const BspModel& world = map.models[0];
  for (int f = world.first_face; f < world.first_face + world.num_faces; ++f) {
    const BspFace& face = map.faces[f];
    const BspShader& shader = map.shaders[face.shader];
    if (face.type != BspFaceType::kPatch || !(shader.contents & contents_mask) ||
        (shader.surface_flags & kSurfNonSolid))
      continue;
    const std::vector<BspVertex> control(map.vertices.begin() + face.first_vertex,
                                         map.vertices.begin() + face.first_vertex + face.num_vertices);
    const TriangleMesh mesh =
        tessellatePatch(control, face.patch_size[0], face.patch_size[1], kPatchCollisionLevel);
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const std::array<Vector3f, 3> triangle{mesh.vertices[mesh.indices[i]].position,
                                             mesh.vertices[mesh.indices[i + 1]].position,
                                             mesh.vertices[mesh.indices[i + 2]].position};
      if (auto brush = facetBrush(triangle, shader.contents)) {
        brush->drawn = !(shader.surface_flags & kSurfNoDraw);
        out.push_back(std::move(*brush));
      }
    }
  }
}

}  // namespace

CollisionModel CollisionModel::fromBsp(const BspMap& map, int contents_mask) {
  if (map.models.empty()) throw InputError(map.name, "no world model");
  std::vector<ConvexBrush> brushes;
  const BspModel& world = map.models[0];
  for (int b = world.first_brush; b < world.first_brush + world.num_brushes; ++b) {
    const BspBrush& brush = map.brushes[b];
    const BspShader& shader = map.shaders[brush.shader];  // the shader that gives the contents
    if (!(shader.contents & contents_mask)) continue;
    ConvexBrush convex;
    convex.contents = shader.contents;
    convex.drawn = !(shader.surface_flags & kSurfNoDraw);
    for (int s = brush.first_side; s < brush.first_side + brush.num_sides; ++s) {
      const BspPlane& plane = map.planes[map.brush_sides[s].plane];
      convex.planes.emplace_back(plane.normal.x(), plane.normal.y(), plane.normal.z(), plane.dist);
    }
    brushes.push_back(std::move(convex));
  }
  addPatchFacets(map, contents_mask, brushes);
  return CollisionModel(std::move(brushes), PlayableWorld::fromBsp(map));
}

PlayableWorld PlayableWorld::fromBsp(const BspMap& map) {
  if (map.models.empty()) throw InputError(map.name, "no world model");
  PlayableWorld w;
  w.bounds = Eigen::AlignedBox3f(map.models[0].mins, map.models[0].maxs);
  w.nodes = map.nodes;
  w.planes = map.planes;
  for (const auto& leaf : map.leafs) w.leaf_clusters.push_back(leaf.cluster);
  return w;
}

bool PlayableWorld::contains(const Eigen::Vector3f& p) const {
  if (!bounds.contains(p)) return false;
  return nodes.empty() || leaf_clusters[bspLeafAt(nodes, planes, p)] >= 0;
}

CollisionModel::CollisionModel(std::vector<ConvexBrush> brushes, std::optional<PlayableWorld> world)
    : world_(std::move(world)) {
  for (auto& brush : brushes)
    if (completeBrush(brush)) brushes_.push_back(std::move(brush));
  for (const auto& brush : brushes_) bounds_.extend(brush.bounds);
  if (brushes_.empty()) return;

  grid_origin_ = bounds_.min().head<2>();
  const Eigen::Vector2f extent = bounds_.max().head<2>() - grid_origin_;
  grid_w_ = std::max(1, static_cast<int>(std::ceil(extent.x() / bucket_size_)));
  grid_h_ = std::max(1, static_cast<int>(std::ceil(extent.y() / bucket_size_)));
  buckets_.resize(static_cast<size_t>(grid_w_) * grid_h_);
  for (size_t i = 0; i < brushes_.size(); ++i) {
    const auto& b = brushes_[i].bounds;
    const Eigen::Vector2i lo = bucketOf(b.min().x(), b.min().y());
    const Eigen::Vector2i hi = bucketOf(b.max().x(), b.max().y());
    first_bucket_.push_back(lo);
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) buckets_[y * grid_w_ + x].push_back(static_cast<int>(i));
  }
}

Eigen::Vector2i CollisionModel::bucketOf(float x, float y) const {
  const int bx = static_cast<int>(std::floor((x - grid_origin_.x()) / bucket_size_));
  const int by = static_cast<int>(std::floor((y - grid_origin_.y()) / bucket_size_));
  return {std::clamp(bx, 0, grid_w_ - 1), std::clamp(by, 0, grid_h_ - 1)};
}

template <typename Fn>
bool CollisionModel::forBrushesNear(const Eigen::AlignedBox3f& box, Fn&& fn) const {
  if (buckets_.empty() || !box.intersects(bounds_)) return false;
  const Eigen::Vector2i lo = bucketOf(box.min().x(), box.min().y());
  const Eigen::Vector2i hi = bucketOf(box.max().x(), box.max().y());
  for (int y = lo.y(); y <= hi.y(); ++y)
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int i : buckets_[y * grid_w_ + x]) {
        // A brush filed in several buckets of the range is visited in the first only.
        const Eigen::Vector2i& first = first_bucket_[i];
        if (x != std::max(lo.x(), first.x()) || y != std::max(lo.y(), first.y())) continue;
        if (brushes_[i].bounds.intersects(box) && fn(brushes_[i])) return true;
      }
  return false;
}

bool CollisionModel::boxInSolid(const Vector3f& center, const Vector3f& mins,
                                const Vector3f& maxs) const {
  const Eigen::AlignedBox3f box(center + mins, center + maxs);
  return forBrushesNear(box, [&](const ConvexBrush& brush) {
    return boxOverlapsBrush(brush, center, mins, maxs);
  });
}

BoxOverlap CollisionModel::boxOverlap(const Vector3f& center, const Vector3f& mins, const Vector3f& maxs) const {
  const Eigen::AlignedBox3f box(center + mins, center + maxs);
  BoxOverlap overlap;
  forBrushesNear(box, [&](const ConvexBrush& brush) {
    if (boxOverlapsBrush(brush, center, mins, maxs)) {
      overlap.contents |= brush.contents;
      overlap.drawn |= brush.drawn;
    }
    return false;
  });
  return overlap;
}

bool CollisionModel::pointInSolid(const Vector3f& p) const {
  return boxInSolid(p, Vector3f::Zero(), Vector3f::Zero());
}

std::optional<float> CollisionModel::dropBox(const Vector3f& start, const Vector3f& mins,
                                             const Vector3f& maxs, float max_drop) const {
  if (max_drop < 0 || boxInSolid(start, mins, maxs)) return std::nullopt;
  const Vector3f end = start - Vector3f(0, 0, max_drop);
  const Eigen::AlignedBox3f swept(end + mins, start + maxs);
  std::optional<float> nearest;
  forBrushesNear(swept, [&](const ConvexBrush& brush) {
    if (auto f = sweepFraction(brush, start, end, mins, maxs); f && (!nearest || *f < *nearest))
      nearest = f;
    return false;
  });
  if (!nearest) return std::nullopt;
  return start.z() - *nearest * max_drop;
}

}  // namespace valerant::quake3
