#pragma once
// What the ONNX models' loaders share (the depth prior, the learned world model): the
// file read whole, with errors that name it, and a blob's shape for error messages.
#include <string>
#include <vector>

namespace cv {
class Mat;
}

namespace valerant {

// The bytes of the model file at `path`; `what` names the model in errors ("depth prior
// model", "world model"). Throws InputError naming the path when it is missing, not a
// regular file or unreadable.
std::vector<unsigned char> readModelFile(const std::string& path, const std::string& what);

// "[1,6,96,128]": the dimensions of an n-dimensional blob.
std::string blobShapeText(const cv::Mat& blob);

}  // namespace valerant
