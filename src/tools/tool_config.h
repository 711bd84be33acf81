#pragma once
// A tool's configuration, through the one strict loader: --config FILE (default: the
// package's file), then the tool's flags that stand for configuration keys, then every
// --set key=value. A bad value is an error naming the flag that gave it, with the same
// range checks as the file.
#include <string>
#include <utility>
#include <vector>

#include "cli_args.h"
#include "valerant/config/config.h"

namespace valerant::tools {

// A flag and the configuration key its value sets ("--budget" -> "policy.budget_steps").
struct FlagKey {
  std::string flag;
  std::string key;
};
// A switch without a value and the assignment it stands for ("--no-rf" -> "floor.enabled=false").
struct SwitchKey {
  std::string flag;
  std::string assignment;
};

inline ConfigDocument toolConfigDocument(const CliArgs& args, const std::vector<FlagKey>& flag_keys = {},
                                         const std::vector<SwitchKey>& switch_keys = {}) {
  ConfigDocument doc = ConfigDocument::load(args.get("--config", defaultConfigPath()));
  for (const auto& [flag, key] : flag_keys)
    if (args.has(flag)) doc.set(key, args.get(flag), flag + " " + args.get(flag));
  for (const auto& [flag, assignment] : switch_keys)
    if (args.has(flag)) doc.setAssignment(assignment, flag);
  for (const auto& assignment : args.sets()) doc.setAssignment(assignment, std::string(CliArgs::kSet) + " " + assignment);
  return doc;
}

}  // namespace valerant::tools
