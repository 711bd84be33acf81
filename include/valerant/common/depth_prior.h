#pragma once
// A learned monocular depth prior: an ONNX net (learn/train_depth.py) run on the CPU by
// OpenCV's DNN module. Interface of the model: input "rgb" float32 NCHW [1,3,H,W], RGB
// in [0,1]; output "depth_and_scale" float32 [1,2,H,W], channel 0 = ln(metric depth in
// metres along the optical axis; sky is trained as 80 m), channel 1 = ln b, b the
// Laplace scale of the ln-depth error (smaller = more confident).
//
// Thread safety: predict() may be called from any number of threads at once. A
// cv::dnn::Net is not safe to forward from two threads, so the instance keeps the
// model's bytes once and a pool of Nets built from them: each call borrows a Net no
// other call is using (building one when all are busy) and returns it afterwards. A
// pool rather than one Net per thread because the branches run on std::async threads
// that live for one step only; the pool grows to the peak number of concurrent calls
// (five branches) and dies with the instance.
#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace valerant {

struct DepthPrediction {
  cv::Mat depth_m;    // CV_32F metres along the optical axis
  cv::Mat log_scale;  // CV_32F ln b of the ln-depth error, same size

  // Both maps resized bilinearly to `size` (e.g. the camera's).
  DepthPrediction resized(cv::Size size) const;
};

class NetPool;

class DepthPrior {
 public:
  // Loads the ONNX file at `model_path` for input frames resized to `net_size` (OpenCV
  // 4.6 cannot read the input size from the file) and runs one probe forward. Throws
  // InputError naming the file when it is missing, unreadable, not a model OpenCV can
  // load, or its output is not [1,2,net_size.height,net_size.width] or half that (a net
  // that reads frames of twice its output size).
  DepthPrior(const std::string& model_path, cv::Size net_size);
  ~DepthPrior();
  DepthPrior(const DepthPrior&) = delete;
  DepthPrior& operator=(const DepthPrior&) = delete;

  // `rgb`: CV_8UC3 RGB of any size, resized (INTER_AREA) to the net's input. The
  // prediction is at the net's output size. Throws InputError for another image type.
  DepthPrediction predict(const cv::Mat& rgb) const;

  const std::string& modelPath() const { return path_; }
  cv::Size netSize() const { return net_size_; }
  // The size of every prediction: netSize(), or half of it.
  cv::Size outputSize() const { return output_size_; }

 private:
  std::string path_;
  cv::Size net_size_;
  cv::Size output_size_;
  std::unique_ptr<NetPool> nets_;
};

}  // namespace valerant
