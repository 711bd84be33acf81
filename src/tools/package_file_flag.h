#pragma once
// A FILE flag whose default is one of the package's own files (config/valerant.yaml,
// config/map_sets.yaml). The package folder comes from the environment (package_dir.h),
// which may not know it (a shell without the workspace sourced): `--help` must still
// work, so the default is looked up for the help without failing, and again when a run
// reads it; only then does a missing package stop the tool, with an error naming the
// flag, the file and the environment searched (exit status 1: the environment's fault,
// not the command line's).
#include <functional>
#include <string>
#include <utility>

#include "command_line.h"

namespace valerant::tools {

class PackageFileFlag {
 public:
  // Adds `flag` to `app`. `default_path` finds the default file and throws InputError
  // when the package is not found; `in_package` is where the file lies in the package
  // ("config/valerant.yaml"), for the help when the package is not found.
  PackageFileFlag(CLI::App& app, const std::string& flag, const std::string& meaning,
                  std::function<std::string()> default_path, std::string in_package)
      : flag_(flag), in_package_(std::move(in_package)), default_path_(std::move(default_path)) {
    option_ = addPath(app, flag, value_, meaning, "FILE")->default_str(defaultForHelp());
  }
  // CLI11 holds the address of value_.
  PackageFileFlag(const PackageFileFlag&) = delete;
  PackageFileFlag& operator=(const PackageFileFlag&) = delete;

  bool given() const { return option_->count() > 0; }

  // The file given, else the default. Throws InputError when the default is needed and
  // the package is not found.
  std::string path() const {
    if (given()) return value_;
    try {
      return default_path_();
    } catch (const InputError& e) {
      throw InputError(flag_ + " left out", e.what());
    }
  }

 private:
  // The default's path, or where it would be when the package is not found.
  std::string defaultForHelp() const {
    try {
      return default_path_();
    } catch (const InputError&) {
      return "the package's " + in_package_ + " (package not found)";
    }
  }

  std::string flag_, in_package_, value_;
  std::function<std::string()> default_path_;
  CLI::Option* option_ = nullptr;
};

}  // namespace valerant::tools
