#include "valerant/common/output_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <vector>

#include "valerant/common/error.h"

namespace valerant {
namespace {

namespace fs = std::filesystem;

std::string systemError(int error) { return std::strerror(error); }

// True when VALERANT_FAIL_WRITES names this file: the test's stand-in for a full disk.
bool injectedFailure(const std::string& path) {
  const char* items = std::getenv("VALERANT_FAIL_WRITES");
  if (!items || !*items) return false;
  std::stringstream in(items);
  for (std::string item; std::getline(in, item, ',');) {
    if (item.empty() || item.size() > path.size()) continue;
    const size_t at = path.size() - item.size();
    if (path.compare(at, item.size(), item) == 0 && (at == 0 || path[at - 1] == '/')) return true;
  }
  return false;
}

void failInjected(const std::string& path) {
  if (injectedFailure(path)) throw InputError(path, "cannot write: " + systemError(ENOSPC) + " (VALERANT_FAIL_WRITES)");
}

// A name beside `path` that no other writer uses: hidden, marked partial, with the pid.
std::string temporaryName(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  return (p.parent_path() / ("." + p.filename().string() + ".partial-" + std::to_string(::getpid()) + "-" +
                             std::to_string(counter++)))
      .string();
}

// Writes all of `bytes` to `fd`, retrying short writes; false with errno on failure.
bool writeAll(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<size_t>(n));
  }
  return true;
}

void syncFile(const std::string& temporary, const std::string& path) {
  const int fd = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(path, "cannot reopen the written file: " + systemError(errno));
  const bool synced = ::fsync(fd) == 0;
  const int error = errno;
  ::close(fd);
  if (!synced) throw InputError(path, "cannot sync: " + systemError(error));
}

// The rename is durable once the folder's entry is synced too.
void syncFolder(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the data is renamed already; a folder we cannot open cannot be synced
  ::fsync(fd);
  ::close(fd);
}

void renameIntoPlace(const std::string& temporary, const std::string& path) {
  if (::rename(temporary.c_str(), path.c_str()) != 0)
    throw InputError(path, "cannot rename " + temporary + " into place: " + systemError(errno));
  syncFolder(path);
}

// Removes the temporary file when the write did not complete.
struct TemporaryGuard {
  std::string path;
  bool keep = false;
  ~TemporaryGuard() {
    if (!keep) ::unlink(path.c_str());
  }
};

}  // namespace

void requireWritable(const std::string& path, bool overwrite) {
  if (!overwrite && fs::exists(path)) throw InputError(path, "exists already (pass --force to overwrite)");
  const auto parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent)) throw InputError(path, "its folder does not exist");
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  failInjected(path);
  TemporaryGuard temporary{temporaryName(path)};
  const int fd = ::open(temporary.path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(path, "cannot create " + temporary.path + ": " + systemError(errno));
  const bool written = writeAll(fd, bytes);
  int error = errno;
  const bool synced = written && ::fsync(fd) == 0;
  if (written && !synced) error = errno;
  if (::close(fd) != 0 && synced) {
    throw InputError(path, "cannot write: " + systemError(errno));
  }
  if (!written) throw InputError(path, "cannot write: " + systemError(error));
  if (!synced) throw InputError(path, "cannot sync: " + systemError(error));
  renameIntoPlace(temporary.path, path);
  temporary.keep = true;
}

void writeThroughTemporary(const std::string& path, const std::string& what,
                           const std::function<bool(const std::string& temporary)>& write) {
  failInjected(path);
  TemporaryGuard temporary{temporaryName(path)};
  bool written = false;
  try {
    written = write(temporary.path);
  } catch (const std::exception& e) {  // PCL throws its own exceptions, naming no file
    throw InputError(path, what + " could not write it: " + e.what());
  }
  if (!written) throw InputError(path, what + " could not write it (is the disk full?)");
  if (!fs::is_regular_file(temporary.path)) throw InputError(path, what + " wrote no file");
  syncFile(temporary.path, path);
  renameIntoPlace(temporary.path, path);
  temporary.keep = true;
}

void writeImageAtomically(const std::string& path, const cv::Mat& image) {
  if (image.empty()) throw InputError(path, "no image to write");
  std::vector<uchar> bytes;
  const std::string extension = fs::path(path).extension().string();
  bool encoded = false;
  try {
    encoded = cv::imencode(extension, image, bytes);
  } catch (const cv::Exception& e) {
    throw InputError(path, std::string("cannot encode the image: ") + e.what());
  }
  if (!encoded) throw InputError(path, "cannot encode the image as " + extension);
  writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

AppendOnlyLog::AppendOnlyLog(const std::string& path, bool append) : path_(path) {
  failInjected(path);
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (append ? O_APPEND : O_TRUNC), 0644);
  if (fd_ < 0) throw InputError(path, "cannot open for writing: " + systemError(errno));
}

AppendOnlyLog::~AppendOnlyLog() {
  if (fd_ >= 0) ::close(fd_);
}

void AppendOnlyLog::writeLine(const std::string& line) {
  failInjected(path_);
  const std::string whole = line + '\n';
  if (!writeAll(fd_, whole)) throw InputError(path_, "cannot write: " + systemError(errno));
  if (::fdatasync(fd_) != 0) throw InputError(path_, "cannot sync: " + systemError(errno));
}

}  // namespace valerant
