#pragma once
// Renders one map's dataset sequences (dataset_sequences.h) with ground truth: moves
// the camera as the engine world does (camera_kinematics.h) and renders only the
// frames it keeps. A sequence ends at its first frame that penetrates the world (the
// player hull inside solid brushes, or outside the playable world:
// CameraKinematics::inSolid) unless `keep_in_solid` (depth there would teach walls
// from inside, or the level's outside).
#include <functional>

#include "valerant/dataset/dataset_sequences.h"
#include "valerant/dataset/shard_writer.h"
#include "valerant/dataset/texture_shuffle.h"
#include "valerant/world/quake3/quake3_map.h"

namespace cv {
class Mat;
}

namespace valerant::dataset {

using FrameSink = std::function<void(const FrameRecord&, const cv::Mat& rgb, const cv::Mat& depth_m)>;

struct MapRenderStats {
  int sequences = 0, frames = 0, in_solid_stops = 0;
};

// `config.world.width/height/fov_x_deg` set the frame size. Throws InputError naming
// the map when it has no spawn with a floor under it. With `shuffle` enabled, each
// sequence draws a new texture assignment (texture_shuffle.h) from its own generator,
// seeded by `seed`, the map and the sequence: the sequences and poses are those of the
// same seed without it.
MapRenderStats renderMapDataset(const quake3::Quake3Map& map, const std::string& map_name, const Config& config,
                                const SamplingParams& params, uint64_t seed, bool keep_in_solid, int first_sequence,
                                const FrameSink& sink, const TextureShuffle& shuffle = {});

}  // namespace valerant::dataset
