#include "valerant/common/output_file.h"

#include <filesystem>

#include "valerant/common/error.h"

namespace valerant {

void requireWritable(const std::string& path, bool overwrite) {
  if (!overwrite && std::filesystem::exists(path))
    throw InputError(path, "exists already (pass --force to overwrite)");
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty() && !std::filesystem::is_directory(parent))
    throw InputError(path, "its folder does not exist");
}

}  // namespace valerant
