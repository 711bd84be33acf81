#pragma once
// A tool's configuration, through the one strict loader: --config FILE (default: the
// package's file, looked up only when a run reads it: package_file_flag.h), then the
// tool's flags that stand for configuration keys, then every --set key=value in
// command-line order. A bad value is an error naming the flag that gave it, with the
// same range checks as the file; as the command line's fault, it exits 2
// (command_line.h), where an error in the file itself exits 1.
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "command_line.h"
#include "package_file_flag.h"
#include "valerant/config/config.h"

namespace valerant::tools {

// Tools that run the game engine themselves (valerant_render, valerant_slam, the render,
// slam and depth benchmarks) refuse another world.backend instead of quietly rendering
// the engine: a usage error naming the setting and where the learned world is measured.
inline void requireEngineWorld(const Config& config, const std::string& tool) {
  if (config.world.backend != "quake3")
    throw UsageError("world.backend " + config.world.backend,
                     tool + " runs the game engine only (world.backend quake3); the learned world is measured by "
                            "valerant_bench wm and explored by valerant_explore");
}

class ToolConfig {
 public:
  // Adds --config and --set to `app`.
  explicit ToolConfig(CLI::App& app)
      : app_(app),
        config_file_(app, "--config", "configuration file; a flag that 'sets KEY' defaults to the file's KEY",
                     defaultConfigPath, "config/valerant.yaml") {
    set_option_ =
        app.add_option("--set", sets_, "override a configuration key, e.g. policy.budget_steps=30 (repeatable)")
            ->type_name("KEY=VALUE")
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
            ->allow_extra_args(false);
  }

  // A flag whose value sets `key` ("--budget" -> "policy.budget_steps"). Without a
  // `tool_default` the configuration's value stands until the flag is given; with one,
  // the flag sets the key always (a --set of the same key still wins).
  CLI::Option* keyFlag(const std::string& flag, const std::string& key, const std::string& type,
                       const std::string& meaning, std::optional<std::string> tool_default = std::nullopt) {
    KeyFlag& f =
        key_flags_.emplace_back(KeyFlag{flag, key, tool_default.value_or(""), nullptr, tool_default.has_value()});
    f.option = app_.add_option(flag, f.value, meaning + " (sets " + key + ")")->type_name(type);
    if (f.always) f.option->default_str(f.value);
    return f.option;
  }

  // A flag without a value that stands for `assignment` ("--no-rf" -> "floor.enabled=false").
  CLI::Option* switchFlag(const std::string& flag, const std::string& assignment, const std::string& meaning) {
    Switch& s = switches_.emplace_back(Switch{flag, assignment, nullptr});
    s.option = app_.add_flag(flag)->description(meaning + " (sets " + assignment + ")");
    return s.option;
  }

  // The configuration as the command line makes it, checked whole; see the header.
  ConfigDocument document() const {
    const std::string file = config_file_.path();
    ConfigDocument doc = ConfigDocument::load(file);
    try {
      for (const KeyFlag& f : key_flags_)
        if (f.always || f.option->count()) doc.set(f.key, f.value, f.flag + " " + f.value);
      for (const Switch& s : switches_)
        if (s.option->count()) doc.setAssignment(s.assignment, s.flag);
      for (const std::string& assignment : sets_) doc.setAssignment(assignment, "--set " + assignment);
      doc.parse();
    } catch (const InputError& e) {
      // An error of the file alone is the file's (exit 1), whatever the overrides. Loaded
      // again: a copy of the document would share the overridden YAML tree.
      ConfigDocument::load(file).parse();
      throw asUsageError(e);
    }
    return doc;
  }

  // The flags given that change the configuration (--config, --set, key flags, switches).
  std::vector<std::string> givenFlags() const {
    std::vector<std::string> given;
    for (const KeyFlag& f : key_flags_)
      if (f.option->count()) given.push_back(f.flag);
    for (const Switch& s : switches_)
      if (s.option->count()) given.push_back(s.flag);
    if (config_file_.given()) given.push_back("--config");
    if (set_option_->count()) given.push_back("--set");
    return given;
  }

  // The configuration file: --config's, else the package's (throws InputError when the
  // package is not found).
  std::string file() const { return config_file_.path(); }
  bool fileGiven() const { return config_file_.given(); }
  const std::vector<std::string>& sets() const { return sets_; }

 private:
  struct KeyFlag {
    std::string flag, key, value;
    CLI::Option* option;
    bool always;  // the flag has a tool default and sets the key even when not given
  };
  struct Switch {
    std::string flag, assignment;
    CLI::Option* option;
  };
  CLI::App& app_;
  PackageFileFlag config_file_;
  std::vector<std::string> sets_;
  CLI::Option* set_option_ = nullptr;
  std::deque<KeyFlag> key_flags_;  // a deque: CLI11 keeps pointers to each value
  std::deque<Switch> switches_;
};

}  // namespace valerant::tools
