#include "valerant/map/walkable_area.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/common/output_file.h"

namespace valerant {
namespace {

constexpr int8_t kFree = 0;
constexpr int8_t kOccupied = 100;

std::vector<cv::Point2f> toCv(const std::vector<Eigen::Vector2d>& ring) {
  std::vector<cv::Point2f> out;
  out.reserve(ring.size());
  for (const auto& p : ring) out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  return out;
}

double ringArea(const std::vector<Eigen::Vector2d>& ring) { return ring.size() < 3 ? 0 : cv::contourArea(toCv(ring)); }

double polygonArea(const WalkablePolygon& p) {
  double area = ringArea(p.outer);
  for (const auto& hole : p.holes) area -= ringArea(hole);
  return area;
}

// >0 inside, 0 on the boundary, <0 outside. Degenerate rings (a point, a line) are
// boundaries only.
double ringTest(const std::vector<Eigen::Vector2d>& ring, const Eigen::Vector2d& p) {
  return cv::pointPolygonTest(toCv(ring), cv::Point2f(static_cast<float>(p.x()), static_cast<float>(p.y())), false);
}

nlohmann::json ringJson(const std::vector<Eigen::Vector2d>& ring) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : ring) out.push_back({p.x(), p.y()});
  return out;
}

std::vector<Eigen::Vector2d> ringFromJson(const nlohmann::json& json, const std::string& path) {
  if (!json.is_array()) throw InputError(path, "a polygon ring is not an array of [x, z] points");
  std::vector<Eigen::Vector2d> ring;
  for (const auto& p : json) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      throw InputError(path, "a polygon point is not [x, z]");
    ring.emplace_back(p[0].get<double>(), p[1].get<double>());
  }
  return ring;
}

double positiveNumber(const nlohmann::json& json, const char* key, const std::string& path) {
  if (!json.contains(key) || !json[key].is_number() || !(json[key].get<double>() >= 0))
    throw InputError(path, std::string("missing or negative '") + key + "'");
  return json[key].get<double>();
}

}  // namespace

double WalkableArea::areaSquareMetres() const {
  double area = 0;
  for (const auto& p : polygons) area += polygonArea(p);
  return area;
}

bool WalkableArea::contains(const Eigen::Vector2d& xz) const {
  for (const auto& p : polygons) {
    if (ringTest(p.outer, xz) < 0) continue;
    bool in_hole = false;
    for (const auto& hole : p.holes) in_hole |= ringTest(hole, xz) > 0;
    if (!in_hole) return true;
  }
  return false;
}

WalkableArea walkableArea(const FloorGrid& grid, const MapFrame& frame, const WalkableParams& params) {
  WalkableArea area;
  area.cell_size_m = grid.resolution * frame.metres_per_unit;
  area.clearance_m = params.clearance * frame.metres_per_unit;
  if (grid.width == 0 || grid.height == 0) return area;

  // Rows of the mask are the grid's rows (v), columns its columns (u).
  cv::Mat free_cells(grid.height, grid.width, CV_8UC1), not_obstacle(grid.height, grid.width, CV_8UC1);
  for (int row = 0; row < grid.height; ++row) {
    for (int col = 0; col < grid.width; ++col) {
      const int8_t v = grid.cells[static_cast<size_t>(row) * grid.width + col];
      free_cells.at<uint8_t>(row, col) = v == kFree ? 255 : 0;
      not_obstacle.at<uint8_t>(row, col) = v == kOccupied ? 0 : 255;
    }
  }
  // Distance (cells, centre to centre) to the nearest obstacle cell; its near edge is
  // half a cell closer.
  cv::Mat distance;
  cv::distanceTransform(not_obstacle, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::Mat walkable;
  const int side = 2 * params.close_cells + 1;
  cv::morphologyEx(free_cells, walkable, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, {side, side}));
  for (int row = 0; row < grid.height; ++row)
    for (int col = 0; col < grid.width; ++col)
      if ((distance.at<float>(row, col) - 0.5) * grid.resolution < params.clearance)
        walkable.at<uint8_t>(row, col) = 0;  // obstacle cells have distance 0: never walkable

  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;  // next, previous, first child, parent
  cv::findContours(walkable, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
  const Eigen::Affine3d to_asset = frame.mapToAsset();
  auto ring = [&](const std::vector<cv::Point>& contour) {
    std::vector<Eigen::Vector2d> out;
    for (const auto& c : contour) {
      const Eigen::Vector2d uv = grid.origin + grid.resolution * Eigen::Vector2d(c.x + 0.5, c.y + 0.5);
      const Eigen::Vector3d p = to_asset * frame.floorPoint(uv);
      out.emplace_back(p.x(), p.z());
    }
    return out;
  };
  for (size_t i = 0; i < contours.size(); ++i) {
    if (hierarchy[i][3] >= 0) continue;  // a hole: taken with its outer ring
    WalkablePolygon polygon;
    polygon.outer = ring(contours[i]);
    for (int h = hierarchy[i][2]; h >= 0; h = hierarchy[h][0]) polygon.holes.push_back(ring(contours[h]));
    const double polygon_area = polygonArea(polygon);
    if (polygon_area > 0 && polygon_area >= params.min_area_m2) area.polygons.push_back(std::move(polygon));
  }
  return area;
}

void writeWalkableJson(const std::string& path, const WalkableArea& area, bool overwrite) {
  requireWritable(path, overwrite);
  nlohmann::json polygons = nlohmann::json::array();
  for (const auto& p : area.polygons) {
    nlohmann::json holes = nlohmann::json::array();
    for (const auto& h : p.holes) holes.push_back(ringJson(h));
    polygons.push_back({{"outer", ringJson(p.outer)}, {"holes", holes}});
  }
  const nlohmann::json json = {
      {"frame", "asset frame (metres, Y up, origin at the spawn's feet); points are (x, z) on the floor"},
      {"cell_size_m", area.cell_size_m},
      {"clearance_m", area.clearance_m},
      {"area_m2", area.areaSquareMetres()},
      {"polygons", polygons}};
  writeFileAtomically(path, json.dump(1) + '\n');
}

WalkableArea readWalkableJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot read");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, "truncated or invalid JSON (" + std::string(e.what()) + ")");
  }
  if (!json.is_object() || !json.contains("polygons") || !json["polygons"].is_array())
    throw InputError(path, "has no 'polygons' array");
  WalkableArea area;
  area.cell_size_m = positiveNumber(json, "cell_size_m", path);
  area.clearance_m = positiveNumber(json, "clearance_m", path);
  for (const auto& p : json["polygons"]) {
    if (!p.is_object() || !p.contains("outer") || !p.contains("holes") || !p["holes"].is_array())
      throw InputError(path, "a polygon lacks 'outer' or 'holes'");
    WalkablePolygon polygon;
    polygon.outer = ringFromJson(p["outer"], path);
    for (const auto& h : p["holes"]) polygon.holes.push_back(ringFromJson(h, path));
    area.polygons.push_back(std::move(polygon));
  }
  return area;
}

}  // namespace valerant
