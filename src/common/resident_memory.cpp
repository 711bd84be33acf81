#include "valerant/common/resident_memory.h"

#include <fstream>
#include <sstream>

namespace valerant {

ResidentMemory parseResidentMemory(const std::string& status_text) {
  ResidentMemory memory;
  std::istringstream lines(status_text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream fields(line);
    std::string name, unit;
    uint64_t kilobytes = 0;
    if (!(fields >> name >> kilobytes >> unit) || unit != "kB") continue;
    if (name == "VmRSS:") memory.current_bytes = kilobytes * 1024;
    if (name == "VmHWM:") memory.peak_bytes = kilobytes * 1024;
  }
  return memory;
}

ResidentMemory residentMemory() {
  std::ifstream in("/proc/self/status");
  std::stringstream text;
  text << in.rdbuf();
  return parseResidentMemory(text.str());
}

}  // namespace valerant
