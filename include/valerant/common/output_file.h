#pragma once
// The one rule every writer of a run's files follows: never overwrite an existing file
// unless asked (--force), and fail before writing when the folder is missing.
#include <string>

namespace valerant {

// Throws InputError naming `path` when it exists and `overwrite` is false, or when its
// folder does not exist.
void requireWritable(const std::string& path, bool overwrite);

}  // namespace valerant
