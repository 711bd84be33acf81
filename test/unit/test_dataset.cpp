// valerant_dataset's parts: the log16 depth code, key strings, map sets, the shard
// writer and one map's rendered sequences.
#include <gtest/gtest.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "openarena_data.h"
#include "valerant/common/error.h"
#include "valerant/dataset/dataset_render.h"
#include "valerant/dataset/log_depth_code.h"
#include "valerant/dataset/map_sets.h"
#include "valerant/dataset/near_wall_cells.h"
#include "valerant/dataset/shard_writer.h"
#include "valerant/dataset/texture_shuffle.h"

using namespace valerant;
using namespace valerant::dataset;
namespace fs = std::filesystem;

namespace {

std::string readEntry(const std::string& zip_path, const std::string& name) {
  int error = 0;
  zip_t* zip = zip_open(zip_path.c_str(), ZIP_RDONLY, &error);
  if (!zip) return "";
  zip_stat_t st;
  std::string data;
  if (zip_stat(zip, name.c_str(), 0, &st) == 0) {
    zip_file_t* f = zip_fopen(zip, name.c_str(), 0);
    data.resize(st.size);
    zip_fread(f, data.data(), st.size);
    zip_fclose(f);
  }
  zip_close(zip);
  return data;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("valerant_test_dataset_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST(LogDepthCode, HandComputedCodes) {
  // ln depth spread over [ln 0.05, ln 200] on codes 1..65535.
  EXPECT_EQ(encodeLogDepth(0.05), 1);
  EXPECT_EQ(encodeLogDepth(200.0), 65535);
  EXPECT_EQ(encodeLogDepth(1000.0), 65535);  // clamped
  // sqrt(0.05 * 200) = 3.1623 m is halfway: 1 + 32767.
  EXPECT_EQ(encodeLogDepth(std::sqrt(10.0)), 32768);
  // 1 m: ln(20) / ln(4000) = 0.361191 of 65534 steps = 23670.26 -> code 23671.
  EXPECT_EQ(encodeLogDepth(1.0), 23671);
  EXPECT_NEAR(decodeLogDepth(23671), 1.0, 1e-4);  // 0.99997: a step is 0.013 %
  EXPECT_DOUBLE_EQ(decodeLogDepth(1), 0.05);
  EXPECT_NEAR(decodeLogDepth(65535), 200.0, 1e-9);
  EXPECT_EQ(encodeLogDepth(std::nan("")), 0);  // sky
  EXPECT_EQ(encodeLogDepth(-1.0), 0);
  EXPECT_TRUE(std::isnan(decodeLogDepth(0)));
  cv::Mat depth(1, 2, CV_32F);
  depth.at<float>(0, 0) = 1.f;
  depth.at<float>(0, 1) = std::nanf("");
  const cv::Mat back = decodeLogDepthImage(encodeLogDepthImage(depth));
  EXPECT_NEAR(back.at<float>(0, 0), 1.f, 1e-4f);
  EXPECT_TRUE(std::isnan(back.at<float>(0, 1)));
}

TEST(DatasetKeys, RunLengthStringsInTheCandidatesVocabulary) {
  MotionStep jw, w, a, still;
  jw.yaw_deg = 1, jw.forward_units = 4;
  w.forward_units = 4;
  a.strafe_units = -4;
  EXPECT_EQ(keysOf(jw), "jw");
  EXPECT_EQ(keysOf(a), "a");
  EXPECT_EQ(keysOf(still), "u");
  const std::vector<MotionStep> steps{jw, jw, jw, w, w};
  EXPECT_EQ(runLengthKeys(steps, 0, 5), "jw:3+w:2");
  EXPECT_EQ(runLengthKeys(steps, 2, 4), "jw:1+w:1");
  EXPECT_EQ(runLengthKeys(steps, 0, 0), "");
  EXPECT_THROW(runLengthKeys(steps, 3, 6), InputError);
  EXPECT_EQ(mapSeed(7, "oa_dm1"), mapSeed(7, "oa_dm1"));
  EXPECT_NE(mapSeed(7, "oa_dm1"), mapSeed(7, "oa_dm2"));
  EXPECT_NE(mapSeed(7, "oa_dm1"), mapSeed(8, "oa_dm1"));
}

TEST(MapSets, TheFixedListsAreDisjoint) {
  const MapSets sets = loadMapSets(defaultMapSetsPath());
  EXPECT_EQ(sets.evaluation.size(), 5u);
  EXPECT_TRUE(sets.isHeldOut("kaos2"));
  EXPECT_TRUE(sets.isHeldOut("kaos"));  // a remake of kaos2
  EXPECT_FALSE(sets.isHeldOut("oa_dm1"));  // a tuning map
  const fs::path dir = freshDir("map_sets");
  std::ofstream(dir / "twice.yaml") << "tuning: [a]\nevaluation: [b, a]\nheld_out_variants: []\n";
  try {
    loadMapSets((dir / "twice.yaml").string());
    FAIL() << "a map in two lists was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a"), std::string::npos);
  }
  std::ofstream(dir / "missing.yaml") << "tuning: [a]\n";
  EXPECT_THROW(loadMapSets((dir / "missing.yaml").string()), InputError);
}

TEST(ShardWriter, WritesAWholeZipWithTheSameBytesForTheSameFrames) {
  const fs::path dir = freshDir("shard");
  ShardMeta meta;
  meta.intrinsics = CameraIntrinsics::fromHorizontalFov(8, 6, 90);
  meta.split = "train";
  meta.eye_height_m = 1.5625;
  cv::Mat rgb(6, 8, CV_8UC3, cv::Scalar(10, 200, 30));
  cv::Mat depth(6, 8, CV_32F, cv::Scalar(2.0f));
  depth.at<float>(0, 0) = std::nanf("");
  FrameRecord r;
  r.map = "oa_dm1";
  r.kind = "rotate";
  r.key = "j:19";
  auto write = [&](const std::string& name) {
    ShardWriter w((dir / name).string(), meta);
    w.add(r, rgb, depth);
    r.step = 19;
    w.add(r, rgb, depth);
    r.step = 0;
    EXPECT_EQ(w.frames(), 2u);
    EXPECT_THROW(w.add(r, cv::Mat(3, 3, CV_8UC3), depth), InputError);
    w.finish();
  };
  write("a.zip");
  write("b.zip");
  EXPECT_FALSE(fs::exists(dir / "a.zip.partial"));
  EXPECT_EQ(fileBytes((dir / "a.zip").string()), fileBytes((dir / "b.zip").string()));
  const std::string csv = readEntry((dir / "a.zip").string(), "frames.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "index,map,spawn,sequence,step,kind,key,x,y,z,yaw_deg,pitch_deg,in_solid");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  EXPECT_NE(csv.find("1,oa_dm1,-1,0,19,rotate,j:19,"), std::string::npos);
  const auto m = nlohmann::json::parse(readEntry((dir / "a.zip").string(), "meta.json"));
  EXPECT_EQ(m["width"], 8);
  EXPECT_EQ(m["depth_encoding"], "log16");
  EXPECT_EQ(m["maps"], nlohmann::json::array({"oa_dm1"}));
  const std::string png = readEntry((dir / "a.zip").string(), "depth/000001.png");
  const cv::Mat codes = cv::imdecode(std::vector<uchar>(png.begin(), png.end()), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(codes.type(), CV_16U);
  EXPECT_EQ(codes.at<uint16_t>(0, 0), 0);  // sky
  EXPECT_EQ(codes.at<uint16_t>(1, 1), encodeLogDepth(2.0));
  EXPECT_FALSE(readEntry((dir / "a.zip").string(), "rgb/000001.jpg").empty());
  // Never over an existing shard.
  EXPECT_THROW(ShardWriter((dir / "a.zip").string(), meta), InputError);
}

TEST(DatasetRender, OneMapsSequencesStayOutOfSolidAndRepeat) {
  VALERANT_REQUIRE_OPENARENA();
  Config config = loadConfig(defaultConfigPath());
  config.world.width = 64;
  config.world.height = 48;
  SamplingParams params;
  params.spawns = 1;
  params.rotations = 1;
  params.walks = 2;
  const auto map = quake3::loadQuake3Map("oa_dm1", config.world.patch_level);
  std::vector<FrameRecord> first, second;
  int sky_or_depth = 0;
  const MapRenderStats stats = renderMapDataset(*map, "oa_dm1", config, params, 3, false, 0,
                                                [&](const FrameRecord& r, const cv::Mat& rgb, const cv::Mat& depth) {
                                                  first.push_back(r);
                                                  EXPECT_EQ(rgb.size(), cv::Size(64, 48));
                                                  sky_or_depth += cv::countNonZero(depth == depth) > 0;
                                                });
  renderMapDataset(*map, "oa_dm1", config, params, 3, false, 0,
                   [&](const FrameRecord& r, const cv::Mat&, const cv::Mat&) { second.push_back(r); });
  // A wall turn comes after the other kinds and leaves their frames as they were.
  SamplingParams with_wall = params;
  with_wall.wall_rotations = 1;
  std::vector<FrameRecord> third;
  const MapRenderStats wall_stats =
      renderMapDataset(*map, "oa_dm1", config, with_wall, 3, false, 0,
                       [&](const FrameRecord& r, const cv::Mat&, const cv::Mat&) { third.push_back(r); });
  EXPECT_EQ(wall_stats.sequences, 5 + 1 + 2 + 1);
  ASSERT_GT(third.size(), first.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(third[i].sequence, first[i].sequence);
    EXPECT_EQ(third[i].yaw_deg, first[i].yaw_deg);
  }
  EXPECT_EQ(third.back().kind, "rotate");
  EXPECT_EQ(third.back().sequence, 8);
  EXPECT_EQ(stats.sequences, 5 + 1 + 2);
  EXPECT_EQ(stats.frames, static_cast<int>(first.size()));
  EXPECT_EQ(sky_or_depth, stats.frames);
  ASSERT_EQ(first.size(), second.size());
  int rotate = 0;
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_FALSE(first[i].in_solid);
    EXPECT_EQ(first[i].key, second[i].key);
    EXPECT_EQ(first[i].eye_m, second[i].eye_m);
    rotate += first[i].kind == "rotate";
  }
  EXPECT_EQ(rotate, 4 * config.rollout.horizon_frames / params.rotation_every + 1);  // 0, 30, ..., 360 deg
}

TEST(TextureShuffle, AssignmentsFollowTheProbabilityAndTheSeed) {
  TexturePool pool;
  pool.paths = {"a.jpg", "b.jpg"};
  pool.images = {cv::Mat(8, 8, CV_8UC3, cv::Scalar(200, 10, 10)), cv::Mat(8, 4, CV_8UC3, cv::Scalar(10, 200, 10))};
  const std::vector<int> shaders{3, 5, 8, 13};
  TextureShuffle shuffle;
  std::mt19937_64 rng(1);
  EXPECT_TRUE(shuffleTextures(shaders, shuffle, rng).empty());  // no pool
  shuffle.pool = &pool;
  EXPECT_TRUE(shuffleTextures(shaders, shuffle, rng).empty());  // probability 0
  shuffle.probability = 1;
  shuffle.flat_fraction = 0;
  shuffle.tint_probability = 0;
  std::mt19937_64 a(7), b(7);
  const auto first = shuffleTextures(shaders, shuffle, a), second = shuffleTextures(shaders, shuffle, b);
  ASSERT_EQ(first.size(), shaders.size());
  for (int s : shaders) {
    ASSERT_EQ(first.count(s), 1u);
    // Untinted: one of the pool's images itself, the same for the same seed.
    EXPECT_TRUE(first.at(s).data == pool.images[0].data || first.at(s).data == pool.images[1].data);
    EXPECT_EQ(first.at(s).data, second.at(s).data);
  }
  // Tinted pool images keep their size, flat colours are uniform.
  shuffle.tint_probability = 1;
  for (const auto& [s, image] : shuffleTextures(shaders, shuffle, rng)) {
    EXPECT_EQ(image.type(), CV_8UC3);
    EXPECT_TRUE(image.size() == pool.images[0].size() || image.size() == pool.images[1].size());
  }
  shuffle.flat_fraction = 1;
  for (const auto& [s, image] : shuffleTextures(shaders, shuffle, rng)) {
    cv::Scalar mean, stddev;
    cv::meanStdDev(image, mean, stddev);
    EXPECT_EQ(stddev[0] + stddev[1] + stddev[2], 0.0);
  }
  // About half of 400 shaders at probability 0.5.
  std::vector<int> many(400);
  std::iota(many.begin(), many.end(), 0);
  shuffle.probability = 0.5;
  const size_t chosen = shuffleTextures(many, shuffle, rng).size();
  EXPECT_GT(chosen, 150u);
  EXPECT_LT(chosen, 250u);
}

TEST(TextureShuffle, PoolAndShuffledFramesOfOneMap) {
  VALERANT_REQUIRE_OPENARENA();
  quake3::Pk3FileSystem pk3;
  pk3.mountDirectory(quake3::Pk3FileSystem::defaultDataDir());
  const TexturePool pool = buildTexturePool(pk3, {"oa_dm1"}, 32);
  ASSERT_GE(pool.images.size(), 10u);
  EXPECT_TRUE(std::is_sorted(pool.paths.begin(), pool.paths.end()));
  EXPECT_EQ(std::adjacent_find(pool.paths.begin(), pool.paths.end()), pool.paths.end());
  for (const auto& image : pool.images) {
    EXPECT_EQ(image.type(), CV_8UC3);
    EXPECT_LE(std::max(image.cols, image.rows), 32);
  }
  // Blended and sky images stay out of the pool.
  EXPECT_EQ(std::count(pool.paths.begin(), pool.paths.end(), "textures/sfx/beam.jpg"), 0);
  EXPECT_THROW(buildTexturePool(pk3, {"no_such_map"}), InputError);

  // The same sequences and depth with and without the shuffle, other colours.
  Config config = loadConfig(defaultConfigPath());
  config.world.width = 64;
  config.world.height = 48;
  SamplingParams params;
  params.spawns = 1;
  params.rotations = 1;
  params.walks = 1;
  const auto map = quake3::loadQuake3Map("oa_dm1", config.world.patch_level);
  struct Frame {
    FrameRecord r;
    cv::Mat rgb, depth;
  };
  auto render = [&](const TextureShuffle& shuffle) {
    std::vector<Frame> frames;
    renderMapDataset(*map, "oa_dm1", config, params, 3, false, 0,
                     [&](const FrameRecord& r, const cv::Mat& rgb, const cv::Mat& depth) {
                       frames.push_back({r, rgb.clone(), depth.clone()});
                     },
                     shuffle);
    return frames;
  };
  TextureShuffle shuffle;
  shuffle.pool = &pool;
  shuffle.probability = 1;
  const auto own = render({}), shuffled = render(shuffle), again = render(shuffle);
  ASSERT_EQ(own.size(), shuffled.size());
  ASSERT_EQ(own.size(), again.size());
  double colour_change = 0;
  for (size_t i = 0; i < own.size(); ++i) {
    EXPECT_EQ(own[i].r.eye_m, shuffled[i].r.eye_m);
    EXPECT_EQ(own[i].r.key, shuffled[i].r.key);
    EXPECT_EQ(cv::countNonZero(own[i].depth == own[i].depth), cv::countNonZero(shuffled[i].depth == shuffled[i].depth));
    EXPECT_EQ(cv::norm(own[i].depth, shuffled[i].depth, cv::NORM_L1, own[i].depth == own[i].depth), 0.0);
    EXPECT_EQ(cv::norm(shuffled[i].rgb, again[i].rgb, cv::NORM_L1), 0.0);  // deterministic
    colour_change += cv::norm(own[i].rgb, shuffled[i].rgb, cv::NORM_L1) / own[i].rgb.total();
  }
  EXPECT_GT(colour_change / own.size(), 20.0);  // mean absolute change per pixel, summed over channels
}

TEST(NearWallCells, CellsWithinTheReachOfAWallOrAStepUp) {
  // A 10 x 1 corridor of cells at z = 0 (x = 0, 16, ..., 144; y = 0), open at both ends
  // only in the sense that nothing lies beyond: the columns x = -16 and x = 160 and
  // every y = +-16 column are missing, so every cell has a wall within one cell along y.
  std::vector<Eigen::Vector3f> corridor;
  for (int i = 0; i < 10; ++i) corridor.emplace_back(16.f * i, 0.f, 0.f);
  EXPECT_EQ(nearWallCells(corridor).size(), 10u);

  // A 13 x 13 room (x, y = 0 .. 192) with walls only outside it: with max_cells 4 a cell
  // is near when it is at most 4 cells from the edge, i.e. its index i or j is < 4 or
  // > 8 (a wall at index -1 or 13 is within 4 cells of index 0..3 and 9..12). The far
  // cells are the 5 x 5 block of indices 4..8: 169 - 25 = 144 near.
  std::vector<Eigen::Vector3f> room;
  for (int i = 0; i < 13; ++i)
    for (int j = 0; j < 13; ++j) room.emplace_back(16.f * i, 16.f * j, 0.f);
  const std::vector<size_t> near = nearWallCells(room);
  EXPECT_EQ(near.size(), 144u);
  for (size_t k : near) {
    const int i = static_cast<int>(room[k].x() / 16.f), j = static_cast<int>(room[k].y() / 16.f);
    EXPECT_TRUE(i < 4 || i > 8 || j < 4 || j > 8) << i << "," << j;
  }

  // The room's centre cell (6, 6) gets a neighbour column (7, 6) that is a 20-unit step
  // up (higher than STEPSIZE 18: a wall from z = 0): the centre becomes near; a 16-unit
  // step (a stair) or a drop to -100 would not make it near.
  std::vector<Eigen::Vector3f> stepped = room;
  for (Eigen::Vector3f& c : stepped)
    if (c.x() == 112.f && c.y() == 96.f) c.z() = 20.f;
  const auto centre_near = [](const std::vector<Eigen::Vector3f>& cells) {
    const std::vector<size_t> n = nearWallCells(cells);
    return std::any_of(n.begin(), n.end(), [&](size_t k) { return cells[k].x() == 96.f && cells[k].y() == 96.f; });
  };
  EXPECT_TRUE(centre_near(stepped));
  for (Eigen::Vector3f& c : stepped)
    if (c.x() == 112.f && c.y() == 96.f) c.z() = 16.f;
  EXPECT_FALSE(centre_near(stepped));
  for (Eigen::Vector3f& c : stepped)
    if (c.x() == 112.f && c.y() == 96.f) c.z() = -100.f;
  EXPECT_FALSE(centre_near(stepped));
}
