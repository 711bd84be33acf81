#include "valerant/world/learned/world_model_net.h"

#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"
#include "valerant/common/model_file.h"

namespace valerant {
namespace {

const char* const kInputName = "frames_and_motion";
const char* const kPoseAnchorInputName = "frames_motion_and_pose_warp";
const char* const kOutputName = "warp_and_fill";
constexpr int kMotionChannels = 4;  // forward_units, strafe_units, yaw_deg, pitch_deg
constexpr int kOutputChannels = 6;  // dx, dy, mask, fill R, G, B
constexpr int kAnchorPlanes = 4;  // the newest frame moved by the geometry (R, G, B), in_view

const char* inputName(WorldWarp warp) { return warp == WorldWarp::kPoseAnchor ? kPoseAnchorInputName : kInputName; }

std::string expectedOutputText(int width, int height) {
  return "[1," + std::to_string(kOutputChannels) + "," + std::to_string(height) + "," + std::to_string(width) +
         "] float32";
}

// Channel `c` of a [1,C,H,W] float blob as an H x W CV_32F header over its data.
cv::Mat plane(const cv::Mat& blob, int c) {
  const int h = blob.size[2], w = blob.size[3];
  return cv::Mat(h, w, CV_32F, const_cast<float*>(blob.ptr<float>(0, c)));
}

}  // namespace

cv::Mat warpAndFill(const cv::Mat& last, const cv::Mat& flow, const cv::Mat& mask, const cv::Mat& fill) {
  CV_Assert(last.type() == CV_8UC3 && flow.type() == CV_32FC2 && mask.type() == CV_32F && fill.type() == CV_32FC3);
  CV_Assert(flow.size() == last.size() && mask.size() == last.size() && fill.size() == last.size());
  // Absolute sampling positions: map = pixel + flow.
  cv::Mat map(flow.size(), CV_32FC2);
  for (int y = 0; y < flow.rows; ++y) {
    const cv::Vec2f* f = flow.ptr<cv::Vec2f>(y);
    cv::Vec2f* m = map.ptr<cv::Vec2f>(y);
    for (int x = 0; x < flow.cols; ++x) m[x] = cv::Vec2f(x + f[x][0], y + f[x][1]);
  }
  // Sampled in float, so the blend rounds to 8 bits once.
  cv::Mat last_unit, warped;
  last.convertTo(last_unit, CV_32FC3, 1.0 / 255.0);
  cv::remap(last_unit, warped, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  cv::Mat mask3, inverse3;
  cv::merge(std::vector<cv::Mat>(3, mask), mask3);
  cv::subtract(cv::Scalar::all(1.0), mask3, inverse3);
  const cv::Mat blended = mask3.mul(warped) + inverse3.mul(fill);
  // convertTo rounds to nearest and saturates: the clamp to [0,1] and the 8-bit rounding.
  cv::Mat next;
  blended.convertTo(next, CV_8UC3, 255.0);
  return next;
}

WorldWarp parseWorldWarp(const std::string& name) {
  for (WorldWarp warp : {WorldWarp::kLastFrame, WorldWarp::kRotationAnchor, WorldWarp::kPoseAnchor})
    if (name == worldWarpName(warp)) return warp;
  throw InputError("world.learned.warp", "'" + name + "' is not a warp: last_frame, rotation_anchor or pose_anchor");
}

const char* worldWarpName(WorldWarp warp) {
  switch (warp) {
    case WorldWarp::kLastFrame: return "last_frame";
    case WorldWarp::kRotationAnchor: return "rotation_anchor";
    case WorldWarp::kPoseAnchor: return "pose_anchor";
  }
  return "?";
}

WorldModelNet::WorldModelNet(const std::string& path, int width, int height, int context_frames, WorldWarp warp,
                             double fov_x_deg, std::shared_ptr<const DepthPrior> depth_prior)
    : path_(path),
      camera_(CameraIntrinsics::fromHorizontalFov(width, height, fov_x_deg)),
      context_frames_(context_frames),
      warp_(warp),
      depth_prior_(std::move(depth_prior)) {
  if (width <= 0 || height <= 0 || context_frames <= 0)
    throw InputError(path, "world model frame size " + std::to_string(width) + "x" + std::to_string(height) +
                               " and context " + std::to_string(context_frames) + " frames must be positive");
  const std::vector<uchar> bytes = readModelFile(path, "world model");
  try {
    net_ = cv::dnn::readNetFromONNX(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  } catch (const cv::Exception& e) {
    throw InputError(path, "not an ONNX model OpenCV " CV_VERSION " can load: " + e.err);
  }
  if (net_.empty()) throw InputError(path, "OpenCV " CV_VERSION " read no layers from this ONNX model");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  if (net_.getLayer(0)->outputNameToIndex(inputName(warp_)) < 0)
    throw InputError(path, std::string("has no input '") + inputName(warp_) + "', which a model of the " +
                               worldWarpName(warp_) + " warp reads (world.learned.warp): it was made for another "
                               "warp; set world.learned.warp to the one its model card names");
  if (warp_ == WorldWarp::kPoseAnchor && !depth_prior_)
    throw InputError(path, "the pose_anchor warp needs the depth prior (world.learned.depth_prior_model)");
  // Probe on zeros: a model of another interface fails here, not in the middle of a run.
  forward(cv::Mat(std::vector<int>{1, inputChannels(), height, width}, CV_32F, cv::Scalar(0)));
}

int WorldModelNet::inputChannels() const {
  return 3 * context_frames_ + kMotionChannels + (warp_ == WorldWarp::kLastFrame ? 0 : kAnchorPlanes);
}

AnchorState WorldModelNet::startAnchor(const cv::Mat& frame_rgb8) const {
  if (warp_ != WorldWarp::kPoseAnchor) return AnchorState::start(frame_rgb8);
  cv::Mat depth = depth_prior_->predict(frame_rgb8).depth_m;
  if (depth.size() != frame_rgb8.size()) cv::resize(depth, depth, frame_rgb8.size(), 0, 0, cv::INTER_LINEAR);
  return AnchorState::start(frame_rgb8, PoseGeometry::start(depth, camera_));
}

cv::Mat WorldModelNet::forward(const cv::Mat& blob) {
  cv::Mat out;
  try {
    net_.setInput(blob, inputName(warp_));
    out = net_.forward(kOutputName);
  } catch (const cv::Exception& e) {
    throw InputError(path_, std::string("OpenCV cannot run the world model with input '") + inputName(warp_) + "' " +
                                blobShapeText(blob) + " (" + std::to_string(context_frames_) + " context frames of " +
                                std::to_string(width()) + "x" + std::to_string(height()) + " with the " +
                                worldWarpName(warp_) + " warp: the size and warp it was made for?) and output '" +
                                kOutputName + "': " + e.err);
  }
  const bool expected = out.dims == 4 && out.size[0] == 1 && out.size[1] == kOutputChannels &&
                        out.size[2] == height() && out.size[3] == width() && out.type() == CV_32F;
  if (!expected)
    throw InputError(path_, std::string("output '") + kOutputName + "' has shape " + blobShapeText(out) +
                                (out.type() == CV_32F ? "" : " (not float32)") + " for input " + blobShapeText(blob) +
                                ", expected " + expectedOutputText(width(), height()));
  return out.clone();  // forward's result may alias the Net's buffers
}

cv::Mat WorldModelNet::next(const std::vector<cv::Mat>& context, const MotionStep& motion, AnchorState& anchor) {
  if (static_cast<int>(context.size()) != context_frames_)
    throw InputError(path_, "world model context has " + std::to_string(context.size()) + " frames, expected " +
                                std::to_string(context_frames_));
  const cv::Size size(width(), height());
  for (size_t k = 0; k < context.size(); ++k)
    if (context[k].type() != CV_8UC3 || context[k].size() != size)
      throw InputError(path_, "world model context frame " + std::to_string(k) + " is a " +
                                  std::to_string(context[k].cols) + "x" + std::to_string(context[k].rows) + " " +
                                  cv::typeToString(context[k].type()) + ", expected a " + std::to_string(width()) +
                                  "x" + std::to_string(height()) + " CV_8UC3 RGB frame");

  cv::Mat blob(std::vector<int>{1, inputChannels(), height(), width()}, CV_32F);
  cv::Mat unit;  // after the loop: the newest frame in [0,1], which the rotation warp samples
  for (int k = 0; k < context_frames_; ++k) {
    context[k].convertTo(unit, CV_32FC3, 1.0 / 255.0);
    std::vector<cv::Mat> rgb;
    cv::split(unit, rgb);
    for (int c = 0; c < 3; ++c) rgb[c].copyTo(plane(blob, 3 * k + c));
  }
  const double motion_values[kMotionChannels] = {motion.forward_units, motion.strafe_units, motion.yaw_deg,
                                                 motion.pitch_deg};
  for (int i = 0; i < kMotionChannels; ++i) plane(blob, 3 * context_frames_ + i).setTo(motion_values[i]);
  WarpSampling geometry;  // where the anchor warps' geometry sends each pixel
  std::optional<PoseGeometry> moved;  // pose_anchor's geometry after this step
  if (warp_ != WorldWarp::kLastFrame) {
    if (anchor.anchor.size() != size || anchor.coords.size() != size || anchor.valid.size() != size ||
        (warp_ == WorldWarp::kPoseAnchor) != anchor.geometry.has_value())
      throw InputError(path_, std::string("the ") + worldWarpName(warp_) + " warp's state is not that of a " +
                                  std::to_string(width()) + "x" + std::to_string(height()) +
                                  " rollout of this warp (not started with startAnchor?)");
    if (warp_ == WorldWarp::kRotationAnchor) {
      geometry = rotationSampling(motion, camera_);
    } else {
      moved = anchor.geometry->moved(motion);
      geometry = poseSampling(anchor.geometry->depthOf(anchor.coords), anchor.geometry->pose, moved->pose, camera_);
    }
    std::vector<cv::Mat> warped;
    cv::split(sampleBilinear(unit, geometry.positions, false), warped);
    const int first = 3 * context_frames_ + kMotionChannels;
    for (int c = 0; c < 3; ++c) warped[c].copyTo(plane(blob, first + c));
    geometry.in_view.copyTo(plane(blob, first + 3));
  }

  const cv::Mat out = forward(blob);
  cv::Mat flow, fill;
  cv::merge(std::vector<cv::Mat>{plane(out, 0), plane(out, 1)}, flow);
  cv::merge(std::vector<cv::Mat>{plane(out, 3), plane(out, 4), plane(out, 5)}, fill);
  if (warp_ == WorldWarp::kLastFrame) return warpAndFill(context.back(), flow, plane(out, 2), fill);
  return anchorStep(anchor, context.back(), geometry.positions + flow, plane(out, 2), fill, moved);
}

}  // namespace valerant
