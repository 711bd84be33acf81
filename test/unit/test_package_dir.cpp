// Finding the package folder the way rospack does: VALERANT_SHARE_DIR first, then the
// entries of ROS_PACKAGE_PATH in order, breadth first, never inside another package,
// an ignored or a hidden folder; a clear error naming what was searched otherwise.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "valerant/common/error.h"
#include "valerant/config/package_dir.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

// A fresh scratch folder per test.
fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("valerant_test_package_dir_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return fs::canonical(dir);
}

// `dir` becomes a package named `name`.
fs::path package(const fs::path& dir, const std::string& name) {
  fs::create_directories(dir);
  std::ofstream(dir / "package.xml") << "<?xml version=\"1.0\"?>\n<package format=\"2\">\n  <name> " << name
                                     << " </name>\n  <version>0.1.0</version>\n</package>\n";
  return dir;
}

std::string errorOf(const std::string& override_dir, const std::string& ros_package_path) {
  try {
    findPackageDir("valerant", override_dir, ros_package_path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PackageDir, OverrideHoldingThePackageWins) {
  const fs::path root = scratch("override");
  const fs::path share = package(root / "prefix/share/valerant", "valerant");
  const fs::path other = package(root / "source", "valerant");
  EXPECT_EQ(findPackageDir("valerant", share.string(), other.string()), share.string());
}

TEST(PackageDir, OverrideWithoutThePackageIsAnErrorNamingIt) {
  const fs::path root = scratch("bad_override");
  package(root / "not_it", "something_else");
  const std::string error = errorOf((root / "not_it").string(), "");
  EXPECT_NE(error.find("VALERANT_SHARE_DIR=" + (root / "not_it").string()), std::string::npos) << error;
  EXPECT_NE(error.find("no package.xml naming valerant"), std::string::npos) << error;
}

TEST(PackageDir, EntryThatIsThePackageFolderItself) {
  // The devel space: ROS_PACKAGE_PATH names the source tree, which holds package.xml.
  const fs::path source = package(scratch("source_tree") / "valerant_checkout", "valerant");
  EXPECT_EQ(findPackageDir("valerant", "", source.string()), source.string());
}

TEST(PackageDir, InstallSpaceShareFolderIsCrawled) {
  // An install space: ROS_PACKAGE_PATH names PREFIX/share, which holds many packages.
  const fs::path share = scratch("install") / "share";
  package(share / "nodelet", "nodelet");
  const fs::path ours = package(share / "valerant", "valerant");
  EXPECT_EQ(findPackageDir("valerant", "", share.string()), ours.string());
}

TEST(PackageDir, FirstEntryOfThePathWins) {
  const fs::path root = scratch("order");
  const fs::path first = package(root / "a/valerant", "valerant");
  package(root / "b/valerant", "valerant");
  EXPECT_EQ(findPackageDir("valerant", "", (root / "a").string() + ":" + (root / "b").string()),
            first.string());
  // Empty and missing entries are passed over, as rospack passes them over.
  EXPECT_EQ(findPackageDir("valerant", "", ":" + (root / "missing").string() + "::" + (root / "a").string()),
            first.string());
}

TEST(PackageDir, NeverInsideAnotherPackageAnIgnoredOrAHiddenFolder) {
  const fs::path root = scratch("skipped");
  package(root / "outer/valerant", "valerant");  // inside package "outer"
  package(root / "outer", "outer");
  package(root / "ignored/valerant", "valerant");  // under CATKIN_IGNORE
  std::ofstream(root / "ignored/CATKIN_IGNORE");
  package(root / "nosubdirs/valerant", "valerant");  // under rospack_nosubdirs
  std::ofstream(root / "nosubdirs/rospack_nosubdirs");
  package(root / ".hidden/valerant", "valerant");  // in a hidden folder
  const std::string error = errorOf("", root.string());
  EXPECT_NE(error.find("ROS_PACKAGE_PATH='" + root.string() + "'"), std::string::npos) << error;
  // A deeper copy elsewhere is still found.
  const fs::path deep = package(root / "src/group/valerant", "valerant");
  EXPECT_EQ(findPackageDir("valerant", "", root.string()), deep.string());
}

TEST(PackageDir, NotFoundNamesThePathAndTheRemedy) {
  const std::string error = errorOf("", "/nonexistent/a:/nonexistent/b");
  EXPECT_NE(error.find("ROS_PACKAGE_PATH='/nonexistent/a:/nonexistent/b'"), std::string::npos) << error;
  EXPECT_NE(error.find("setup.bash"), std::string::npos) << error;
  EXPECT_NE(error.find("VALERANT_SHARE_DIR"), std::string::npos) << error;
  EXPECT_NE(errorOf("", "").find("ROS_PACKAGE_PATH=''"), std::string::npos);
}

TEST(PackageDir, FilePathsResolveInsideTheOverride) {
  const fs::path share = package(scratch("file_path") / "share/valerant", "valerant");
  const char* saved = std::getenv("VALERANT_SHARE_DIR");
  const std::string previous = saved ? saved : "";
  ::setenv("VALERANT_SHARE_DIR", share.c_str(), 1);
  EXPECT_EQ(packageShareDir(), share.string());
  EXPECT_EQ(packageFilePath("models/depth_prior.onnx"), (share / "models/depth_prior.onnx").string());
  EXPECT_EQ(packageFilePath("/abs/model.onnx"), "/abs/model.onnx");  // absolute: as given
  if (saved)
    ::setenv("VALERANT_SHARE_DIR", previous.c_str(), 1);
  else
    ::unsetenv("VALERANT_SHARE_DIR");
}

TEST(PackageDir, AFilePathWithoutThePackageNamesTheFileAndTheSearch) {
  const fs::path empty = scratch("no_package");
  const char* saved = std::getenv("VALERANT_SHARE_DIR");
  const std::string previous = saved ? saved : "";
  ::setenv("VALERANT_SHARE_DIR", empty.c_str(), 1);
  try {
    packageFilePath("models/depth_prior.onnx");
    ADD_FAILURE() << "no package, no path";
  } catch (const InputError& e) {
    EXPECT_EQ(e.input(), "the package's models/depth_prior.onnx");
    EXPECT_EQ(std::string(e.what()), "the package's models/depth_prior.onnx: VALERANT_SHARE_DIR=" +
                                         empty.string() + ": holds no package.xml naming valerant");
  }
  EXPECT_EQ(packageFilePath("/abs/model.onnx"), "/abs/model.onnx");  // an absolute path needs no package
  if (saved)
    ::setenv("VALERANT_SHARE_DIR", previous.c_str(), 1);
  else
    ::unsetenv("VALERANT_SHARE_DIR");
}

TEST(PackageDir, TheBuildTreeFindsTheSourceTree) {
  // scripts/env.sh and catkin's test environment put the source tree on ROS_PACKAGE_PATH.
  EXPECT_EQ(packageShareDir(), fs::canonical(VALERANT_SOURCE_DIR).string());
}
