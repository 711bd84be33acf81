#pragma once
// A file of fused keyframe points (binary compressed PCD): x y z rgb confidence, h (the
// point's floor-normalised height) and keyframe (the index of its keyframe in the map's
// keyframe list). A run directory keeps its whole map in one such file (run_map.h); a
// snapshot keeps it in parts, each written once (run_snapshot.h).
#include <memory>
#include <string>
#include <vector>

#include "valerant/map/map_fusion.h"

namespace valerant {

// Writes the points of keyframes[first, end) to `path`, atomically (output_file.h);
// returns the number of points. A part without points is still a valid file.
size_t writeKeyframePoints(const std::string& path, const std::vector<std::shared_ptr<const FusedKeyframe>>& keyframes,
                           size_t first, size_t end);

// Reads such a file into `keyframes` (each point goes to the keyframe its index names);
// returns the number of points. A missing, unreadable or inconsistent file (a field
// missing, an index beyond `keyframes`) throws InputError naming `path`.
size_t readKeyframePoints(const std::string& path, const std::vector<std::shared_ptr<FusedKeyframe>>& keyframes);

}  // namespace valerant
