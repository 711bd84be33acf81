#include "valerant/common/model_file.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/core.hpp>

#include "valerant/common/error.h"

namespace valerant {

std::vector<unsigned char> readModelFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, what + " file does not exist");
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, what + " is not a file");
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw InputError(path, "cannot read the " + what + " file");
  return bytes;
}

std::string blobShapeText(const cv::Mat& blob) {
  std::string text = "[";
  for (int d = 0; d < blob.dims; ++d) text += (d ? "," : "") + std::to_string(blob.size[d]);
  return text + "]";
}

}  // namespace valerant
