#include "valerant/config/package_dir.h"

#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <system_error>

#include "valerant/common/error.h"

namespace valerant {
namespace fs = std::filesystem;
namespace {

constexpr const char* kPackage = "valerant";

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

// The <name> of the package.xml in `dir`, or "" when there is none (or it is unreadable).
std::string packageName(const fs::path& dir) {
  std::ifstream in(dir / "package.xml");
  if (!in) return "";
  std::stringstream text;
  text << in.rdbuf();
  static const std::regex name(R"(<name>\s*([^<\s]+)\s*</name>)");
  std::smatch match;
  const std::string xml = text.str();
  return std::regex_search(xml, match, name) ? match[1].str() : "";
}

bool present(const fs::path& path) {
  std::error_code ignored;
  return fs::exists(path, ignored);
}

// Breadth first under `root`; "" when no folder there holds `package`. Unreadable
// folders are skipped, as rospack skips them.
std::string crawl(const fs::path& root, const std::string& package) {
  std::deque<fs::path> queue{root};
  while (!queue.empty()) {
    const fs::path dir = queue.front();
    queue.pop_front();
    if (present(dir / "package.xml")) {
      if (packageName(dir) == package) return fs::weakly_canonical(dir).string();
      continue;  // a package's subfolders hold no other package
    }
    if (present(dir / "CATKIN_IGNORE") || present(dir / "rospack_nosubdirs")) continue;
    std::error_code error;
    for (fs::directory_iterator it(dir, error), end; !error && it != end; it.increment(error)) {
      std::error_code kind;
      if (it->is_directory(kind) && it->path().filename().string().rfind('.', 0) != 0)
        queue.push_back(it->path());
    }
  }
  return "";
}

}  // namespace

std::string findPackageDir(const std::string& package, const std::string& share_dir_override,
                           const std::string& ros_package_path) {
  if (!share_dir_override.empty()) {
    if (packageName(share_dir_override) != package)
      throw InputError("VALERANT_SHARE_DIR=" + share_dir_override, "holds no package.xml naming " + package);
    return fs::weakly_canonical(share_dir_override).string();
  }
  std::stringstream entries(ros_package_path);
  for (std::string entry; std::getline(entries, entry, ':');)
    if (!entry.empty() && present(entry))
      if (std::string found = crawl(entry, package); !found.empty()) return found;
  throw InputError("ROS_PACKAGE_PATH='" + ros_package_path + "'",
                   "no folder there holds the " + package +
                       " package (its package.xml); source the setup.bash of the workspace that built or "
                       "installed it, or set VALERANT_SHARE_DIR to its share folder");
}

std::string packageShareDir() {
  return findPackageDir(kPackage, environment("VALERANT_SHARE_DIR"), environment("ROS_PACKAGE_PATH"));
}

std::string packageFilePath(const std::string& path) {
  if (fs::path(path).is_absolute()) return path;
  try {
    return (fs::path(packageShareDir()) / path).string();
  } catch (const InputError& e) {
    throw InputError("the package's " + path, e.what());  // which file needed the package
  }
}

}  // namespace valerant
