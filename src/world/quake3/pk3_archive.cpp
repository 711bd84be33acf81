#include "valerant/world/quake3/pk3_archive.h"

#include <zip.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "valerant/common/error.h"

namespace valerant::quake3 {
namespace {

std::string hex32(uint32_t v) {
  char text[11];
  std::snprintf(text, sizeof text, "0x%08x", v);
  return text;
}

// zlib's CRC-32 (the zip format's) of `bytes`, in pieces that fit zlib's uInt.
uint32_t crc32Of(const std::vector<uint8_t>& bytes) {
  uLong crc = crc32(0L, Z_NULL, 0);
  constexpr size_t kPiece = size_t{1} << 30;
  for (size_t at = 0; at < bytes.size(); at += kPiece)
    crc = crc32(crc, bytes.data() + at, static_cast<uInt>(std::min(kPiece, bytes.size() - at)));
  return static_cast<uint32_t>(crc);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

struct Pk3FileSystem::Archive {
  std::string path;
  zip_t* zip = nullptr;
  ~Archive() {
    if (zip) zip_discard(zip);
  }
};

Pk3FileSystem::Pk3FileSystem() = default;
Pk3FileSystem::~Pk3FileSystem() = default;

std::string Pk3FileSystem::defaultDataDir() {
  if (const char* env = std::getenv("VALERANT_OA_DATA"); env && *env) {
    if (!std::filesystem::is_directory(env))
      throw InputError(std::string("VALERANT_OA_DATA=") + env, "not a directory");
    return env;
  }
  const std::string debian = "/usr/share/games/openarena/baseoa";
  if (!std::filesystem::is_directory(debian))
    throw InputError(debian, "OpenArena data not installed (apt-get install openarena-data)");
  return debian;
}

void Pk3FileSystem::mountDirectory(const std::string& dir) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir)) throw InputError(dir, "not a directory");
  std::vector<std::string> pk3s;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file() && lower(entry.path().extension().string()) == ".pk3")
      pk3s.push_back(entry.path().string());
  }
  if (pk3s.empty()) throw InputError(dir, "no .pk3 archives found");
  // The game loads pk3s in alphabetical order; later ones override earlier ones.
  std::sort(pk3s.begin(), pk3s.end());
  for (const auto& p : pk3s) mountArchive(p);
}

void Pk3FileSystem::mountArchive(const std::string& path) {
  int error = 0;
  zip_t* zip = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &error);
  if (!zip) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, error);
    std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw InputError(path, "cannot open pk3 archive: " + why);
  }
  auto archive = std::make_unique<Archive>();
  archive->path = path;
  archive->zip = zip;
  const zip_int64_t n = zip_get_num_entries(zip, 0);
  std::lock_guard<std::mutex> lock(mutex_);
  const size_t index = archives_.size();
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* name = zip_get_name(zip, i, 0);
    if (!name || !*name || name[std::char_traits<char>::length(name) - 1] == '/') continue;
    entries_[lower(name)] = Entry{index, i};
  }
  archives_.push_back(std::move(archive));
}

std::optional<std::vector<uint8_t>> Pk3FileSystem::read(const std::string& path) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = entries_.find(lower(path));
  if (it == entries_.end()) return std::nullopt;
  const Archive& archive = *archives_[it->second.archive];
  zip_stat_t st;
  if (zip_stat_index(archive.zip, it->second.index, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
    throw InputError(archive.path + ":" + path, "cannot stat archive entry");
  const std::string entry = archive.path + ":" + ((st.valid & ZIP_STAT_NAME) && st.name ? st.name : path);
  zip_file_t* file = zip_fopen_index(archive.zip, it->second.index, 0);
  if (!file) throw InputError(entry, "cannot open archive entry (corrupt pk3?)");
  std::vector<uint8_t> bytes(st.size);
  const zip_int64_t got = bytes.empty() ? 0 : zip_fread(file, bytes.data(), bytes.size());
  // Read on past the recorded size: libzip checks an entry's CRC only when a read
  // reaches the end of its data, which a read of exactly the entry size never does.
  uint8_t past_end;
  const zip_int64_t more = got < 0 ? 0 : zip_fread(file, &past_end, 1);
  const int error = got < 0 || more < 0 ? zip_error_code_zip(zip_file_get_error(file)) : ZIP_ER_OK;
  const std::string why = error == ZIP_ER_OK ? "" : std::string(": ") + zip_file_strerror(file);
  zip_fclose(file);
  const bool complete = got >= 0 && static_cast<zip_uint64_t>(got) == st.size;
  // The CRC-32 of the bytes read against the one the archive records, whether or not
  // libzip noticed the mismatch on the way.
  const bool crc_known = complete && (st.valid & ZIP_STAT_CRC);
  const uint32_t crc = crc_known ? crc32Of(bytes) : 0;
  if (error == ZIP_ER_CRC || (crc_known && crc != st.crc))
    throw InputError(entry, "CRC-32 mismatch" +
                                (crc_known ? ": the archive records " + hex32(st.crc) + ", the data read has " + hex32(crc)
                                           : std::string()) +
                                " (damaged pk3)");
  if (error != ZIP_ER_OK || !complete) throw InputError(entry, "truncated or corrupt archive entry" + why);
  if (more > 0) throw InputError(entry, "archive entry longer than its recorded size " + std::to_string(st.size));
  return bytes;
}

bool Pk3FileSystem::exists(const std::string& path) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.count(lower(path)) > 0;
}

std::vector<std::string> Pk3FileSystem::list(const std::string& prefix,
                                             const std::string& suffix) const {
  const std::string p = lower(prefix), s = lower(suffix);
  std::vector<std::string> out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = entries_.lower_bound(p); it != entries_.end(); ++it) {
    const std::string& name = it->first;
    if (name.compare(0, p.size(), p) != 0) break;
    if (name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0)
      out.push_back(name);
  }
  return out;
}

std::string Pk3FileSystem::archiveOf(const std::string& path) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = entries_.find(lower(path));
  return it == entries_.end() ? "" : archives_[it->second.archive]->path;
}

}  // namespace valerant::quake3
