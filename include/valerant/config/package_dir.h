#pragma once
// Where the package's own files are (config/, models/, launch/, rviz/): the folder that
// holds valerant's package.xml. That is the source tree in a devel space and
// <prefix>/share/valerant once installed. The ROS-free core cannot ask rospack, so it
// searches the way rospack does (docs/install.md).
#include <string>

namespace valerant {

// The package folder from the process environment: VALERANT_SHARE_DIR when set, else
// the first folder found on ROS_PACKAGE_PATH. Throws InputError naming what was
// searched when neither holds it.
std::string packageShareDir();

// `path` if absolute, else that path inside packageShareDir(); when the package is not
// found, the InputError names `path` as well.
std::string packageFilePath(const std::string& path);

// The search itself, with the environment passed in: `share_dir_override` (may be empty)
// must hold a package.xml naming `package`; otherwise every entry of
// `ros_package_path` (':'-separated) is crawled in order, breadth first, the first
// folder whose package.xml names `package` wins. As rospack does, a folder holding a
// package.xml is not descended into, nor one marked CATKIN_IGNORE or
// rospack_nosubdirs, nor a hidden one.
std::string findPackageDir(const std::string& package, const std::string& share_dir_override,
                           const std::string& ros_package_path);

}  // namespace valerant
