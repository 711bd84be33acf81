#pragma once
// Brush collision model of a Quake III map: the convex solid brushes of the world
// model plus its solid Bezier patches (as thin triangle brushes), queried with
// axis-aligned boxes like the game's CM_BoxTrace. Used only for kinematics (the eye
// follows the floor) and ground truth (in-solid flags, reachable floor); the
// exploration pipeline never sees it.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "valerant/world/quake3/bsp.h"

namespace valerant::quake3 {

struct ConvexBrush {
  std::vector<Eigen::Vector4f> planes;  // (normal, dist): inside means normal.p < dist for all
  Eigen::AlignedBox3f bounds;           // set from the planes by CollisionModel, which
                                        // also adds missing axial bounding planes
  int contents = 0;
  bool drawn = true;  // its shader draws a surface (not nodraw): a camera can see it
};

// What a box overlaps: the contents bits (kContents*) of every brush it is in, OR-ed
// (0: none), and whether any of those brushes is drawn.
struct BoxOverlap {
  int contents = 0;
  bool drawn = false;
};

// Where the playable world ends. A point is outside it when it lies outside the world
// model's bounds (BSP model 0) or, with the BSP tree, in a leaf without a cluster: the
// void beyond the level's sealed hull (or the inside of a structural brush), which the
// game never shows. A camera that walked through an outer wall is there.
struct PlayableWorld {
  Eigen::AlignedBox3f bounds;      // the world model's bounds (inclusive)
  std::vector<BspNode> nodes;      // the world BSP tree (one parseBsp accepts: no cycle);
                                   // empty: the bounds alone decide
  std::vector<BspPlane> planes;
  std::vector<int> leaf_clusters;  // per leaf

  static PlayableWorld fromBsp(const BspMap& map);
  bool contains(const Eigen::Vector3f& p) const;
};

class CollisionModel {
 public:
  // Brushes and patches of the world model (model 0) whose shader contents match
  // `contents_mask`, and the playable world of the map.
  static CollisionModel fromBsp(const BspMap& map,
                                int contents_mask = kContentsSolid | kContentsPlayerClip);
  // `world`: where the playable world ends; without one every point is inside it.
  explicit CollisionModel(std::vector<ConvexBrush> brushes, std::optional<PlayableWorld> world = std::nullopt);

  // True when the box [center+mins, center+maxs] overlaps the interior of a brush.
  bool boxInSolid(const Eigen::Vector3f& center, const Eigen::Vector3f& mins,
                  const Eigen::Vector3f& maxs) const;
  bool pointInSolid(const Eigen::Vector3f& p) const;
  BoxOverlap boxOverlap(const Eigen::Vector3f& center, const Eigen::Vector3f& mins, const Eigen::Vector3f& maxs) const;
  // True when `p` lies outside the playable world (see PlayableWorld); never without one.
  bool pointOutsideWorld(const Eigen::Vector3f& p) const { return world_ && !world_->contains(p); }
  const std::optional<PlayableWorld>& playableWorld() const { return world_; }

  // Sweeps the box straight down from `start` by at most `max_drop`; returns the z
  // of the box centre where it first rests on a solid (its bottom then touches the
  // surface), or nullopt when nothing is below within the range or the box starts
  // in solid.
  std::optional<float> dropBox(const Eigen::Vector3f& start, const Eigen::Vector3f& mins,
                               const Eigen::Vector3f& maxs, float max_drop) const;

  const std::vector<ConvexBrush>& brushes() const { return brushes_; }
  Eigen::AlignedBox3f bounds() const { return bounds_; }

 private:
  std::vector<ConvexBrush> brushes_;
  Eigen::AlignedBox3f bounds_;
  std::optional<PlayableWorld> world_;
  // Uniform XY bucket grid over brush bounds so queries test only nearby brushes.
  float bucket_size_ = 128.f;
  Eigen::Vector2f grid_origin_;
  int grid_w_ = 0, grid_h_ = 0;
  std::vector<std::vector<int>> buckets_;
  std::vector<Eigen::Vector2i> first_bucket_;  // per brush: lowest bucket it is filed in
  Eigen::Vector2i bucketOf(float x, float y) const;
  // Calls fn(brush) for every brush whose bounds touch `box`, each once, until fn
  // returns true; returns whether it did.
  template <typename Fn>
  bool forBrushesNear(const Eigen::AlignedBox3f& box, Fn&& fn) const;
};

}  // namespace valerant::quake3
