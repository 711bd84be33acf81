#pragma once
// Tests on real maps need Debian's OpenArena data (scripts/setup installs it); they
// skip with a clear message only where it is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "valerant/world/quake3/pk3_archive.h"

namespace valerant::test {

inline bool openArenaInstalled() {
  return std::filesystem::is_directory("/usr/share/games/openarena/baseoa");
}

#define VALERANT_REQUIRE_OPENARENA()                                                   \
  if (!::valerant::test::openArenaInstalled())                                        \
  GTEST_SKIP() << "OpenArena data not installed (scripts/setup installs openarena-data)"

}  // namespace valerant::test
