#include "valerant/common/depth_prior.h"

#include <mutex>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "valerant/common/error.h"
#include "valerant/common/model_file.h"

namespace valerant {
namespace {

const char* const kInputName = "rgb";
const char* const kOutputName = "depth_and_scale";

}  // namespace

// Nets built from one model's bytes, each used by one call at a time (see the header).
class NetPool {
 public:
  NetPool(std::vector<uchar> model, const std::string& path) : model_(std::move(model)), path_(path) {}

  // A Net no other caller holds: an idle one, else a new one (built outside the lock,
  // so the first concurrent calls do not wait for each other).
  cv::dnn::Net take() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!idle_.empty()) {
        cv::dnn::Net net = std::move(idle_.back());
        idle_.pop_back();
        return net;
      }
    }
    return build();
  }

  // Hands a Net back for the next caller. A Net whose forward threw is not returned.
  void put(cv::dnn::Net net) {
    std::lock_guard<std::mutex> lock(mutex_);
    idle_.push_back(std::move(net));
  }

 private:
  cv::dnn::Net build() const {
    cv::dnn::Net net;
    try {
      net = cv::dnn::readNetFromONNX(reinterpret_cast<const char*>(model_.data()), model_.size());
    } catch (const cv::Exception& e) {
      throw InputError(path_, "not an ONNX model OpenCV " CV_VERSION " can load: " + e.err);
    }
    if (net.empty()) throw InputError(path_, "OpenCV " CV_VERSION " read no layers from this ONNX model");
    net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    return net;
  }

  const std::vector<uchar> model_;
  const std::string path_;
  std::mutex mutex_;
  std::vector<cv::dnn::Net> idle_;
};

namespace {

// The output sizes a net may have for an input of `input`: the same, or half of it for a
// net that reads frames of twice its output size (learn/valerant_learn/depth_net.py).
bool isOutputSizeFor(cv::Size output, cv::Size input) {
  return output == input || (output.width * 2 == input.width && output.height * 2 == input.height);
}

// One forward pass of `blob` (float32 [1,3,H,W]); returns the output, which must be
// [1,2,h,w] with (w,h) == `output_size` (on the probe, when that is empty, (W,H) or
// (W/2,H/2)), as its own copy (forward's result may alias the Net's buffers).
cv::Mat forward(cv::dnn::Net& net, const cv::Mat& blob, const std::string& path, cv::Size output_size) {
  cv::Mat out;
  try {
    net.setInput(blob, kInputName);
    out = net.forward(kOutputName);
  } catch (const cv::Exception& e) {
    throw InputError(path, std::string("OpenCV cannot run the model with input '") + kInputName + "' " +
                               blobShapeText(blob) + " (the size it was made for?) and output '" + kOutputName +
                               "': " + e.err);
  }
  const cv::Size input(blob.size[3], blob.size[2]);
  const bool planes = out.dims == 4 && out.size[0] == 1 && out.size[1] == 2 && out.type() == CV_32F;
  const cv::Size size = planes ? cv::Size(out.size[3], out.size[2]) : cv::Size();
  const bool expected =
      planes && (output_size.empty() ? isOutputSizeFor(size, input) : size == output_size);
  if (!expected) {
    const std::string wanted =
        output_size.empty()
            ? "[1,2," + std::to_string(input.height) + "," + std::to_string(input.width) + "] or [1,2," +
                  std::to_string(input.height / 2) + "," + std::to_string(input.width / 2) + "]"
            : "[1,2," + std::to_string(output_size.height) + "," + std::to_string(output_size.width) + "]";
    throw InputError(path, std::string("output '") + kOutputName + "' has shape " + blobShapeText(out) +
                               (out.type() == CV_32F ? "" : " (not float32)") + " for input " + blobShapeText(blob) +
                               ", expected " + wanted + " float32");
  }
  return out.clone();
}

}  // namespace

DepthPrediction DepthPrediction::resized(cv::Size size) const {
  DepthPrediction out;
  cv::resize(depth_m, out.depth_m, size, 0, 0, cv::INTER_LINEAR);
  cv::resize(log_scale, out.log_scale, size, 0, 0, cv::INTER_LINEAR);
  return out;
}

DepthPrior::DepthPrior(const std::string& model_path, cv::Size net_size)
    : path_(model_path), net_size_(net_size) {
  if (net_size.width <= 0 || net_size.height <= 0)
    throw InputError(model_path, "net input size " + std::to_string(net_size.width) + "x" +
                                     std::to_string(net_size.height) + " is not positive");
  nets_ = std::make_unique<NetPool>(readModelFile(model_path, "depth prior model"), model_path);
  // Probe: a wrong interface fails here, not in the middle of a run.
  cv::dnn::Net net = nets_->take();
  const cv::Mat probe =
      forward(net, cv::Mat(std::vector<int>{1, 3, net_size.height, net_size.width}, CV_32F, cv::Scalar(0.5)), path_,
              cv::Size());
  output_size_ = cv::Size(probe.size[3], probe.size[2]);
  nets_->put(std::move(net));
}

DepthPrior::~DepthPrior() = default;

DepthPrediction DepthPrior::predict(const cv::Mat& rgb) const {
  if (rgb.empty() || rgb.type() != CV_8UC3)
    throw InputError(path_, "depth prior input must be a non-empty CV_8UC3 RGB frame, got a " +
                                std::to_string(rgb.cols) + "x" + std::to_string(rgb.rows) + " " +
                                cv::typeToString(rgb.type()));
  cv::Mat small;
  cv::resize(rgb, small, net_size_, 0, 0, cv::INTER_AREA);
  // Channel order stays RGB (swapRB false); 8-bit levels scaled to [0,1].
  const cv::Mat blob = cv::dnn::blobFromImage(small, 1.0 / 255.0, cv::Size(), cv::Scalar(), false, false, CV_32F);

  cv::dnn::Net net = nets_->take();
  const cv::Mat out = forward(net, blob, path_, output_size_);
  nets_->put(std::move(net));

  // [1,2,h,w] viewed as the two channel planes stacked: rows [0,h) ln depth, [h,2h) ln b.
  const int h = out.size[2], w = out.size[3];
  const cv::Mat planes = out.reshape(1, std::vector<int>{2 * h, w});
  DepthPrediction p;
  cv::exp(planes.rowRange(0, h), p.depth_m);
  p.log_scale = planes.rowRange(h, 2 * h);
  return p;
}

}  // namespace valerant
