#pragma once
// How every file the tools and nodes write reaches the disk. A file is written under a
// temporary name in its own folder, every write and library return is checked, the
// data is fsync'd, then renamed over the final name: a reader (or a crash) sees the old
// file, no file, or the whole new file, never a cut one. Any failure (a full disk, a
// file-size limit, a library that reports an error) throws InputError naming the final
// path and the reason, and leaves no temporary file behind.
//
// Fault injection for tests: VALERANT_FAIL_WRITES=item[,item...] makes the writes of
// the files whose final path ends with an item ("map.pcd", "run/map.pcd") fail as a full
// disk would.
#include <functional>
#include <opencv2/core/mat.hpp>
#include <string>
#include <string_view>

namespace valerant {

// Throws InputError naming `path` when it exists and `overwrite` is false, or when its
// folder does not exist.
void requireWritable(const std::string& path, bool overwrite);

// Writes `bytes` as the whole file `path`, atomically.
void writeFileAtomically(const std::string& path, std::string_view bytes);

// For libraries that only write to a path (PCL, OpenCV's writers): `write` writes the
// temporary path it is given and returns false (or throws) on failure; the result is
// checked, fsync'd and renamed to `path`. `what` names the writer in errors.
void writeThroughTemporary(const std::string& path, const std::string& what,
                           const std::function<bool(const std::string& temporary)>& write);

// An image, encoded by the extension of `path` (png, jpg, pgm), written atomically.
void writeImageAtomically(const std::string& path, const cv::Mat& image);

// A log that grows a line at a time (decisions.jsonl): each line goes to disk in one
// checked write and is fsync'd, so a killed process leaves whole lines only.
class AppendOnlyLog {
 public:
  // `append` false starts the file empty (truncating one that exists).
  AppendOnlyLog(const std::string& path, bool append);
  ~AppendOnlyLog();
  AppendOnlyLog(const AppendOnlyLog&) = delete;
  AppendOnlyLog& operator=(const AppendOnlyLog&) = delete;
  void writeLine(const std::string& line);

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace valerant
