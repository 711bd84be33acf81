#include "valerant/map/map_frame.h"

#include <cmath>

#include "valerant/common/error.h"
#include "valerant/world/quake3/units.h"

namespace valerant {

Eigen::Affine3d MapFrame::mapToAsset() const {
  Eigen::Matrix3d rotation;  // rows: the asset axes in map coordinates
  rotation.row(0) = forward.cross(up).transpose();  // +X: right of the start heading
  rotation.row(1) = up.transpose();                 // +Y: up
  rotation.row(2) = -forward.transpose();           // +Z: behind, so the spawn looks along -Z
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.linear() = metres_per_unit * rotation;
  t.translation() = -(t.linear() * foot);
  return t;
}

FloorPlane MapFrame::anchorFloor() const {
  FloorPlane f;
  f.q = foot;
  f.n = up;
  f.c = foot + eye_height * up;
  f.reliable = true;
  return f;
}

Eigen::Vector2d MapFrame::floorCoordinates(const Eigen::Vector3d& map_point) const {
  const Eigen::Vector3d d = map_point - foot;
  return {d.dot(forward), d.dot(up.cross(forward))};
}

Eigen::Vector3d MapFrame::floorPoint(const Eigen::Vector2d& uv) const {
  return foot + uv.x() * forward + uv.y() * up.cross(forward);
}

MapFrame mapFrameOf(const FloorPlane& anchor, const Eigen::Vector3d& heading, bool metric_slam, const Config& config) {
  MapFrame f;
  f.eye_height = anchor.cameraHeight();
  if (!(f.eye_height > 0)) throw InputError("anchor floor", "the start camera is not above it: no scale");
  // The same frame as CoverageGrid's: foot point below the camera, heading levelled.
  f.up = anchor.n.normalized();
  f.foot = anchor.c - f.eye_height * f.up;
  f.forward = heading - heading.dot(f.up) * f.up;
  if (f.forward.norm() < 1e-9) f.forward = f.up.unitOrthogonal();  // looking straight down
  f.forward.normalize();
  if (metric_slam) {
    f.metres_per_unit = 1;
    f.scale_source = "metric slam";
  } else {
    f.metres_per_unit = config.world.eye_height_units / quake3::kUnitsPerMetre / f.eye_height;
    f.scale_source = "eye height";
  }
  return f;
}

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

const nlohmann::json& field(const nlohmann::json& json, const std::string& key, const std::string& source) {
  if (!json.is_object() || !json.contains(key)) throw InputError(source, "map frame: missing '" + key + "'");
  return json.at(key);
}

double number(const nlohmann::json& json, const std::string& key, const std::string& source) {
  const auto& v = field(json, key, source);
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw InputError(source, "map frame: '" + key + "' is not a finite number");
  return v.get<double>();
}

Eigen::Vector3d vector3(const nlohmann::json& json, const std::string& key, const std::string& source) {
  const auto& v = field(json, key, source);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError(source, "map frame: '" + key + "' is not three numbers");
  const Eigen::Vector3d out(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!out.allFinite()) throw InputError(source, "map frame: '" + key + "' is not finite");
  return out;
}

}  // namespace

nlohmann::json toJson(const MapFrame& frame) {
  return {{"foot", vec(frame.foot)},
          {"up", vec(frame.up)},
          {"forward", vec(frame.forward)},
          {"eye_height", frame.eye_height},
          {"metres_per_unit", frame.metres_per_unit},
          {"scale_source", frame.scale_source}};
}

MapFrame mapFrameFromJson(const nlohmann::json& json, const std::string& source) {
  MapFrame f;
  f.foot = vector3(json, "foot", source);
  f.up = vector3(json, "up", source);
  f.forward = vector3(json, "forward", source);
  if (std::abs(f.up.norm() - 1) > 1e-6 || std::abs(f.forward.norm() - 1) > 1e-6)
    throw InputError(source, "map frame: 'up' and 'forward' must be unit vectors");
  f.eye_height = number(json, "eye_height", source);
  f.metres_per_unit = number(json, "metres_per_unit", source);
  if (!(f.eye_height > 0) || !(f.metres_per_unit > 0))
    throw InputError(source, "map frame: eye_height and metres_per_unit must be positive");
  if (std::abs(f.up.dot(f.forward)) > 1e-6) throw InputError(source, "map frame: 'forward' is not level");
  const auto& s = field(json, "scale_source", source);
  if (!s.is_string()) throw InputError(source, "map frame: 'scale_source' is not a string");
  f.scale_source = s.get<std::string>();
  return f;
}

}  // namespace valerant
