// valerant_render: renders candidate rollouts of the engine world from a spawn point
// and writes frames, ground-truth depth, the TUM trajectory, in-solid flags and a
// contact sheet per candidate. One JSON line on stdout; logs on stderr.
//
//   valerant_render --map oa_dm1 [--spawn 0] [--candidate uw|jw|lw|jq|lq|KEYS]
//                   [--config FILE] [--set key=value ...] [--every N] --out DIR   (--help: every flag)
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "command_line.h"
#include "tool_config.h"
#include "valerant/common/contact_sheet.h"
#include "valerant/common/output_file.h"
#include "valerant/common/tum_trajectory.h"
#include "valerant/world/quake3/quake3_world.h"

using namespace valerant;
namespace fs = std::filesystem;

namespace {

// 16-bit PNG depth in millimetres (0 = unknown), the TUM RGB-D convention scaled 1000.
cv::Mat depthToPng16(const cv::Mat& depth_m) {
  cv::Mat mm(depth_m.size(), CV_16UC1);
  for (int r = 0; r < depth_m.rows; ++r) {
    for (int c = 0; c < depth_m.cols; ++c) {
      const float d = depth_m.at<float>(r, c);
      mm.at<uint16_t>(r, c) = std::isfinite(d) ? cv::saturate_cast<uint16_t>(d * 1000.f) : 0;
    }
  }
  return mm;
}

void writePng(const std::string& path, const cv::Mat& rgb_or_depth) {
  cv::Mat out;  // a new buffer: converting in place would recolour the caller's frame
  if (rgb_or_depth.type() == CV_8UC3) {
    cv::cvtColor(rgb_or_depth, out, cv::COLOR_RGB2BGR);
  } else {
    out = rgb_or_depth;
  }
  writeImageAtomically(path, out);
}

nlohmann::json writeRollout(const Rollout& r, const std::string& dir, int every) {
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  std::vector<Eigen::Isometry3d> poses;
  std::ostringstream solid;
  solid << "# frame in_solid floor_z\n";
  int in_solid = 0;
  for (size_t i = 0; i < r.frames.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof(name), "%06zu.png", i);
    if (i % every == 0 || i + 1 == r.frames.size()) {
      writePng(dir + "/rgb/" + name, r.frames[i]);
      writePng(dir + "/depth/" + name, depthToPng16(r.truth[i].depth_m));
    }
    poses.push_back(r.truth[i].camera_to_world);
    solid << i << ' ' << r.truth[i].in_solid << ' ' << r.truth[i].floor_z << '\n';
    in_solid += r.truth[i].in_solid;
  }
  writeFileAtomically(dir + "/in_solid.txt", solid.str());
  writeTumTrajectory(dir + "/gt_trajectory.txt", poses);
  writePng(dir + "/contact_sheet.png", makeContactSheet(r.frames, r.candidate));
  return {{"candidate", r.candidate}, {"frames", r.frames.size()}, {"in_solid_frames", in_solid}, {"dir", dir}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Renders the candidate rollouts of the engine world from a spawn point: frames, true depth, "
      "trajectory, in-solid flags and a contact sheet per candidate.",
      "valerant_render"};
  tools::useToolConventions(app);
  tools::ToolConfig tool_config(app);
  tool_config.keyFlag("--map", "world.map", "MAP", "map name or PK3:MAP");
  tool_config.keyFlag("--spawn", "world.spawn", "INT", "spawn point index");
  std::string out, candidate;
  int every = 1;
  tools::addPath(app, "--out", out, "output folder", "DIR")->required();
  const CLI::Option* candidate_flag =
      app.add_option("--candidate", candidate, "one rollout: uw, jw, lw, jq, lq or a key string (default: all five)")
          ->type_name("KEYS");
  tools::addInteger(app, "--every", every, "write the images of every Nth frame (and the last)", 1);
  return tools::runTool(app, argc, argv, [&] {
    const Config config = tool_config.document().parse();
    tools::requireEngineWorld(config, "valerant_render");
    std::vector<std::string> candidates = candidateNames();
    if (candidate_flag->count()) candidates = {candidate};
    std::vector<ActionSequence> sequences;  // validated before any rendering
    tools::checkFlagValues([&] {
      for (const auto& c : candidates) sequences.push_back(makeActionSequence(c, config));
    });

    auto map = quake3::loadQuake3Map(config.world.map, config.world.patch_level);
    quake3::Quake3World world(map, config);
    std::cerr << "valerant_render: " << config.world.map << " spawn " << config.world.spawn << ", "
              << sequences.size() << " rollouts\n";
    fs::create_directories(out);
    writePng(out + "/spawn.png", world.context().frames.back());

    nlohmann::json rollouts = nlohmann::json::array();
    const CheckpointId start = world.checkpoint();
    for (const auto& seq : sequences) {
      world.restore(start);
      const Rollout r = world.rollout(seq);
      const std::string dir = out + "/" + (seq.name.find(':') == std::string::npos ? seq.name : "custom");
      rollouts.push_back(writeRollout(r, dir, every));
    }
    const auto& stats = world.textureStats();
    nlohmann::json line = {{"tool", "valerant_render"},
                           {"map", config.world.map},
                           {"spawn", config.world.spawn},
                           {"out", out},
                           {"textures", {{"images", stats.images}, {"shader_stages", stats.shader_stages},
                                         {"placeholders", stats.placeholders}}},
                           {"rollouts", rollouts}};
    std::cout << line.dump() << std::endl;
    return 0;
  });
}
