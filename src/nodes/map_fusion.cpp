// map_fusion: the explorer's global map as ROS products, extended after every step by
// the new keyframes (LiveMap; rebuilt after a rewind) with the same product code as
// MapFusion in the explorer and valerant_explore.
//   sub map_update (valerant/MapUpdate), decision (valerant/Decision)
//   pub (latched) map/cloud (PointCloud2 x y z rgb confidence, voxel-filtered),
//       map/octomap (occupied OctoMap voxel centres as a cloud), map/grid
//       (nav_msgs/OccupancyGrid of the floor band), map/path (nav_msgs/Path of the
//       committed camera), map/candidates (MarkerArray: the step's five branches
//       coloured by verdict, the chosen one wider), map/failed_cells (MarkerArray)
//   file ~bt_path: the OctoMap .bt, rewritten after every update ("" = none)
#include <filesystem>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <octomap/ColorOcTree.h>
#include <optional>
#include <ros/ros.h>
#include <valerant/Decision.h>
#include <valerant/MapUpdate.h>
#include <visualization_msgs/MarkerArray.h>

#include "valerant/common/error.h"
#include "valerant/geometry/coverage_grid.h"
#include "valerant/map/live_map.h"
#include "valerant/map/map_exports.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_config.h"
#include "valerant/ros/node_main.h"

using namespace valerant;

namespace {

struct Colour {
  float r, g, b;
};
// The topdown image's verdict colours (topdown_image.h).
constexpr Colour kAdmissible{0.1f, 0.8f, 0.1f}, kCollision{0.9f, 0.1f, 0.1f}, kFailedRegion{1.0f, 0.55f, 0.0f},
    kLost{0.5f, 0.5f, 0.5f}, kFailedCell{0.9f, 0.1f, 0.1f};

Colour verdictColour(const valerant::Verdict& v) {
  if (v.slam_lost || v.floor_unknown) return kLost;  // not judged
  if (valerant::bridge::fromMsg(v).predictsCollision()) return kCollision;
  if (v.enters_failed || v.rewound_before) return kFailedRegion;
  return kAdmissible;
}

class MapFusionNode {
 public:
  MapFusionNode(::ros::NodeHandle nh, ::ros::NodeHandle pnh)
      : config_(valerant::bridge::loadGraphConfig(nh)),
        bt_path_(pnh.param<std::string>("bt_path", "")),
        line_width_(valerant::bridge::requiredDouble(pnh, "line_width")),
        chosen_width_(valerant::bridge::requiredDouble(pnh, "chosen_line_width")),
        failed_alpha_(valerant::bridge::requiredDouble(pnh, "failed_cell_alpha")),
        failed_height_(valerant::bridge::requiredDouble(pnh, "failed_cell_height")) {
    cloud_ = nh.advertise<sensor_msgs::PointCloud2>("map/cloud", 1, true);
    octomap_ = nh.advertise<sensor_msgs::PointCloud2>("map/octomap", 1, true);
    grid_ = nh.advertise<nav_msgs::OccupancyGrid>("map/grid", 1, true);
    path_ = nh.advertise<nav_msgs::Path>("map/path", 1, true);
    candidates_ = nh.advertise<visualization_msgs::MarkerArray>("map/candidates", 1, true);
    failed_ = nh.advertise<visualization_msgs::MarkerArray>("map/failed_cells", 1, true);
    updates_ = nh.subscribe("map_update", 1, &MapFusionNode::onUpdate, this);
    decisions_ = nh.subscribe("decision", 16, &MapFusionNode::onDecision, this);
  }

 private:
  void onUpdate(const valerant::MapUpdate::ConstPtr& m) {
    try {
      if (m->keyframes.size() != m->keyframe_poses.size())
        throw InputError("map update " + std::to_string(m->step), "keyframes and poses differ in number");
      if (m->failed_cells.size() % 2) throw InputError("map update " + std::to_string(m->step), "odd failed-cell list");
      if (m->keyframe_ids.size() != m->keyframes.size())
        throw InputError("map update " + std::to_string(m->step), "keyframes and ids differ in number");
      const FloorPlane anchor = valerant::bridge::fromMsg(m->grid_anchor);
      const double kappa = anchor.cameraHeight();
      if (!(kappa > 0) || !std::isfinite(kappa)) throw InputError("map update grid anchor", "camera height not positive");
      const CoverageGrid grid(config_.policy, anchor, {m->grid_heading.x, m->grid_heading.y, m->grid_heading.z},
                              config_.world.d_fwd_units / config_.world.eye_height_units);
      // A new episode (another anchor) starts a new mirror.
      if (!live_ || m->grid_anchor != anchor_ || m->grid_heading != heading_) {
        live_ = std::make_unique<LiveMap>(config_.map, config_.collision, grid, kappa);
        anchor_ = m->grid_anchor;
        heading_ = m->grid_heading;
      }
      // Only keyframes the mirror does not hold at the same place are converted.
      std::vector<std::shared_ptr<const FusedKeyframe>> keyframes;
      for (size_t i = 0; i < m->keyframes.size(); ++i) {
        const auto& held = live_->keyframes();
        if (i < held.size() && held[i]->id == m->keyframe_ids[i]) {
          keyframes.push_back(held[i]);
          continue;
        }
        auto kf = std::make_shared<FusedKeyframe>();
        kf->id = m->keyframe_ids[i];
        kf->camera_to_map = valerant::bridge::fromMsg(m->keyframe_poses[i]);
        kf->points = valerant::bridge::fromFusedCloudMsg(m->keyframes[i]);
        keyframes.push_back(std::move(kf));
      }
      live_->update(keyframes);
      const ::ros::Time stamp = m->header.stamp;
      publishCloud(stamp);
      publishOctomap(stamp);
      publishGrid(grid, stamp);
      publishPath(*m);
      publishFailed(*m, grid, stamp);
      grid_geometry_.emplace(grid);
    } catch (const std::exception& e) {
      ROS_ERROR_STREAM("map_fusion: " << e.what());
    }
  }

  void publishCloud(const ::ros::Time& stamp) {
    std::vector<CloudPoint> points;
    for (const auto& p : live_->voxelCloud())
      points.push_back({p.position, p.rgb, p.confidence});
    sensor_msgs::PointCloud2 msg = valerant::bridge::toCloudMsg(points, "map");
    msg.header.stamp = stamp;
    cloud_.publish(msg);
  }

  void publishOctomap(const ::ros::Time& stamp) {
    if (live_->keyframes().empty()) return;
    const octomap::ColorOcTree& tree = live_->octree();
    std::vector<CloudPoint> centres;
    for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
      if (!tree.isNodeOccupied(*it)) continue;
      const octomap::point3d c = it.getCoordinate();
      const octomap::ColorOcTreeNode::Color colour = it->getColor();
      centres.push_back({{c.x(), c.y(), c.z()}, {colour.r, colour.g, colour.b}, static_cast<float>(it->getOccupancy())});
    }
    sensor_msgs::PointCloud2 msg = valerant::bridge::toCloudMsg(centres, "map");
    msg.header.stamp = stamp;
    octomap_.publish(msg);
    if (!bt_path_.empty()) {
      std::filesystem::create_directories(std::filesystem::path(bt_path_).parent_path());
      writeOctreeBt(bt_path_, tree, true);
    }
  }

  void publishGrid(const CoverageGrid& grid, const ::ros::Time& stamp) {
    const FloorGrid& g = live_->floorGrid();
    // The grid's axes in the map frame: u along the start heading, v = n x u.
    const int mid = grid.size() / 2;
    const Eigen::Vector3d origin = grid.cellCentre({mid, mid});
    const Eigen::Vector3d u = (grid.cellCentre({mid + 1, mid}) - origin).normalized();
    const Eigen::Vector3d v = (grid.cellCentre({mid, mid + 1}) - origin).normalized();
    Eigen::Matrix3d axes;
    axes << u, v, u.cross(v);
    Eigen::Isometry3d corner = Eigen::Isometry3d::Identity();
    corner.linear() = axes;
    corner.translation() = origin + g.origin.x() * u + g.origin.y() * v;
    nav_msgs::OccupancyGrid msg;
    msg.header.stamp = stamp;
    msg.header.frame_id = "map";
    msg.info.map_load_time = stamp;
    msg.info.resolution = static_cast<float>(g.resolution);
    msg.info.width = g.width;
    msg.info.height = g.height;
    msg.info.origin = valerant::bridge::toPoseMsg(corner);
    msg.data.assign(g.cells.begin(), g.cells.end());
    grid_.publish(msg);
  }

  void publishPath(const valerant::MapUpdate& m) {
    nav_msgs::Path path;
    path.header = m.header;
    for (const auto& p : m.trajectory) {
      geometry_msgs::PoseStamped pose;
      pose.header = m.header;
      pose.pose = valerant::bridge::toPoseMsg(valerant::bridge::fromMsg(p));
      path.poses.push_back(pose);
    }
    path_.publish(path);
  }

  void publishFailed(const valerant::MapUpdate& m, const CoverageGrid& grid, const ::ros::Time& stamp) {
    visualization_msgs::Marker cubes;
    cubes.header.frame_id = "map";
    cubes.header.stamp = stamp;
    cubes.ns = "failed_cells";
    cubes.type = visualization_msgs::Marker::CUBE_LIST;
    cubes.action = m.failed_cells.empty() ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
    cubes.pose.orientation.w = 1;
    cubes.scale.x = cubes.scale.y = grid.cellSize();
    cubes.scale.z = grid.cellSize() * failed_height_;
    cubes.color.r = kFailedCell.r, cubes.color.g = kFailedCell.g, cubes.color.b = kFailedCell.b;
    cubes.color.a = static_cast<float>(failed_alpha_);
    for (size_t i = 0; i + 1 < m.failed_cells.size(); i += 2) {
      const Eigen::Vector3d c = grid.cellCentre({m.failed_cells[i], m.failed_cells[i + 1]});
      geometry_msgs::Point p;
      p.x = c.x(), p.y = c.y(), p.z = c.z();
      cubes.points.push_back(p);
    }
    visualization_msgs::MarkerArray array;
    array.markers.push_back(cubes);
    failed_.publish(array);
  }

  void onDecision(const valerant::Decision::ConstPtr& d) {
    visualization_msgs::MarkerArray array;
    visualization_msgs::Marker clear;
    clear.action = visualization_msgs::Marker::DELETEALL;
    array.markers.push_back(clear);
    for (size_t i = 0; i < d->verdicts.size(); ++i) {
      const auto& v = d->verdicts[i];
      visualization_msgs::Marker line;
      line.header.frame_id = "map";
      line.header.stamp = d->header.stamp;
      line.ns = "candidates";
      line.id = static_cast<int>(i);
      line.type = visualization_msgs::Marker::LINE_STRIP;
      line.action = visualization_msgs::Marker::ADD;
      line.pose.orientation.w = 1;
      const bool chosen = v.candidate == d->chosen;
      const double cell = grid_geometry_ ? grid_geometry_->cellSize() : 1.0;
      line.scale.x = (chosen ? chosen_width_ : line_width_) * cell;
      const Colour c = verdictColour(v);
      line.color.r = c.r, line.color.g = c.g, line.color.b = c.b, line.color.a = 1;
      line.points = v.centres;
      line.text = v.candidate + (v.reason.empty() ? "" : ": " + v.reason);
      array.markers.push_back(line);
    }
    candidates_.publish(array);
  }

  Config config_;
  std::string bt_path_;
  double line_width_, chosen_width_;  // in coverage cells
  double failed_alpha_, failed_height_;  // failed cells: opacity, height in coverage cells
  std::optional<CoverageGrid> grid_geometry_;
  std::unique_ptr<LiveMap> live_;  // the episode's map, mirrored
  valerant::Floor anchor_;         // and the grid it was made for
  geometry_msgs::Vector3 heading_;
  ::ros::Publisher cloud_, octomap_, grid_, path_, candidates_, failed_;
  ::ros::Subscriber updates_, decisions_;
};

}  // namespace

int main(int argc, char** argv) { return valerant::bridge::spinNode<MapFusionNode>(argc, argv, "map_fusion"); }
