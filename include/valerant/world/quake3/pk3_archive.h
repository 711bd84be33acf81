#pragma once
// Quake III virtual file system over .pk3 (zip) archives, read with libzip.
// Archives mounted later override earlier ones for the same path, exactly as the
// game's search path does (pak0 < pak1 < ... sorted by file name).
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace valerant::quake3 {

class Pk3FileSystem {
 public:
  Pk3FileSystem();
  ~Pk3FileSystem();
  Pk3FileSystem(const Pk3FileSystem&) = delete;
  Pk3FileSystem& operator=(const Pk3FileSystem&) = delete;

  // The folder holding OpenArena's baseoa pk3s: $VALERANT_OA_DATA if set, else the
  // Debian location. Throws InputError when no such folder exists.
  static std::string defaultDataDir();

  // Mounts every *.pk3 below `dir` (recursively), in game order (sorted by name).
  void mountDirectory(const std::string& dir);
  // Mounts one archive on top of everything mounted so far. Throws InputError on a
  // missing or corrupt archive, naming it.
  void mountArchive(const std::string& path);

  // Case-insensitive lookup like the game; nullopt when no mounted archive has it.
  std::optional<std::vector<uint8_t>> read(const std::string& path) const;
  bool exists(const std::string& path) const;
  // Every path (lower case) that starts with `prefix` and ends with `suffix`.
  std::vector<std::string> list(const std::string& prefix, const std::string& suffix) const;
  // The archive that provides `path` (for error messages), or "".
  std::string archiveOf(const std::string& path) const;
  size_t archiveCount() const { return archives_.size(); }

 private:
  struct Archive;
  struct Entry {
    size_t archive;
    int64_t index;
  };
  std::vector<std::unique_ptr<Archive>> archives_;
  std::map<std::string, Entry> entries_;  // lower-cased path -> newest provider
  mutable std::mutex mutex_;              // libzip handles are not thread safe
};

}  // namespace valerant::quake3
