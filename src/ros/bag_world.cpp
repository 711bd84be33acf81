#include "valerant/ros/bag_world.h"

#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <valerant/Context.h>
#include <valerant/Frame.h>

#include "valerant/common/error.h"
#include "valerant/ros/conversions.h"
#include "valerant/ros/graph_names.h"

namespace valerant::bridge {
namespace {

Rollout framesToRollout(const std::vector<valerant::Frame::ConstPtr>& frames) {
  Rollout r;
  for (const auto& f : frames) {
    r.frames.push_back(fromCompressedImageMsg(f->rgb));
    for (const auto& t : f->truth) r.truth.push_back(fromMsg(t));
  }
  return r;
}

// A message of the type's name but another definition (md5) is a bag recorded by an
// older valerant: Frame once carried raw images, which this build cannot read.
template <class M>
boost::shared_ptr<M> instantiate(const rosbag::MessageInstance& m, const std::string& path, const std::string& topic) {
  boost::shared_ptr<M> msg = m.instantiate<M>();
  if (msg) return msg;
  const std::string type = ::ros::message_traits::datatype<M>();
  if (m.getDataType() == type)
    throw InputError("bag " + path, topic + " holds " + type + " of an older message format (md5 " + m.getMD5Sum() +
                                        ", this build reads " + ::ros::message_traits::md5sum<M>() +
                                        "; bags recorded before the frames were PNG-compressed): record it again "
                                        "with record.launch");
  throw InputError("bag " + path, topic + " is a " + m.getDataType() + ", not a " + type);
}

// rosbag record stores relative topic names as given ("world_model/context") and
// absolute ones with their slash; both name the same topic here.
std::string withoutLeadingSlash(const std::string& topic) {
  return !topic.empty() && topic.front() == '/' ? topic.substr(1) : topic;
}

}  // namespace

BagWorld::BagWorld(const std::string& path, const std::string& prefix) : path_(path) {
  std::string root = withoutLeadingSlash(prefix);
  if (!root.empty() && root.back() != '/') root += '/';
  const std::string info_topic = root + kWorldModel + "/camera_info";
  const std::string context_topic = root + kWorldModel + "/context";
  try {
    bag_ = std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Read);
    bool have_info = false, have_context = false;
    rosbag::View view(*bag_);
    for (const rosbag::MessageInstance& m : view) {
      const std::string topic = withoutLeadingSlash(m.getTopic());
      if (topic == info_topic) {
        const auto info = instantiate<sensor_msgs::CameraInfo>(m, path, topic);
        intrinsics_.width = static_cast<int>(info->width);
        intrinsics_.height = static_cast<int>(info->height);
        intrinsics_.fx = info->K[0], intrinsics_.cx = info->K[2], intrinsics_.fy = info->K[4], intrinsics_.cy = info->K[5];
        have_info = true;
      } else if (topic == context_topic && !have_context) {
        const auto context = instantiate<valerant::Context>(m, path, topic);
        std::vector<valerant::Frame::ConstPtr> frames;
        for (const auto& f : context->frames) frames.push_back(boost::make_shared<valerant::Frame>(f));
        context_ = framesToRollout(frames);
        context_.candidate = "context";
        have_context = true;
      } else if (topic.rfind(root + "branch/", 0) == 0 && topic.size() > 7 &&
                 topic.compare(topic.size() - 7, 7, "/frames") == 0) {
        const auto frame = instantiate<valerant::Frame>(m, path, topic);
        auto& list = rollouts_[{frame->key.checkpoint_id, frame->key.candidate}];
        // A rollout recorded twice at one checkpoint (never in one episode): keep the first.
        if (list.size() < frame->key.count && (list.empty() || frame->key.index == list.size())) list.push_back(m);
      }
    }
    if (!have_info) throw InputError(path, "holds no " + info_topic + " (record it with record.launch)");
    if (!have_context) throw InputError(path, "holds no " + context_topic + " (record it with record.launch)");
  } catch (const rosbag::BagException& e) {
    throw InputError("bag " + path, std::string("unreadable: ") + e.what());
  } catch (const ::ros::Exception& e) {
    throw InputError("bag " + path, std::string("corrupt: ") + e.what());
  }
  frames_committed_ = context_.frames.size();
}

CheckpointId BagWorld::checkpoint() {
  current_ = next_checkpoint_++;
  checkpoints_[current_] = frames_committed_;
  return current_;
}

void BagWorld::restore(CheckpointId id) {
  const auto it = checkpoints_.find(id);
  if (it == checkpoints_.end()) throw InputError("checkpoint " + std::to_string(id), "unknown or already dropped");
  frames_committed_ = it->second;
  current_ = id;
  pending_.clear();
}

Rollout BagWorld::rollout(const ActionSequence& actions) {
  const auto it = rollouts_.find({current_, actions.name});
  if (it == rollouts_.end())
    throw InputError("bag " + path_, "has no rollout of " + actions.name + " at checkpoint " + std::to_string(current_) +
                                         " (the replay left the recorded episode)");
  std::vector<valerant::Frame::ConstPtr> frames;
  try {
    for (const auto& m : it->second) frames.push_back(instantiate<valerant::Frame>(m, path_, m.getTopic()));
  } catch (const ::ros::Exception& e) {
    throw InputError("bag " + path_, std::string("corrupt rollout: ") + e.what());
  }
  if (frames.empty() || frames.size() != frames.front()->key.count)
    throw InputError("bag " + path_, "rollout of " + actions.name + " at checkpoint " + std::to_string(current_) +
                                         " is incomplete");
  Rollout r = framesToRollout(frames);
  r.id = next_rollout_++;
  r.candidate = actions.name;
  pending_[r.id] = r.frames.size();
  return r;
}

void BagWorld::commit(const Rollout& rollout) {
  const auto it = pending_.find(rollout.id);
  if (it == pending_.end())
    throw InputError("rollout " + std::to_string(rollout.id),
                     "was not made from the current committed state (stale after a commit or restore)");
  frames_committed_ += it->second;
  pending_.clear();
}

}  // namespace valerant::bridge
