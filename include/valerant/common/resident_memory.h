#pragma once
// This process's resident memory, as Linux reports it in /proc/self/status: now (VmRSS)
// and the most it has held (VmHWM). For progress lines and reports of long runs.
#include <cstdint>
#include <string>

namespace valerant {

struct ResidentMemory {
  uint64_t current_bytes = 0;  // VmRSS
  uint64_t peak_bytes = 0;     // VmHWM
};

// The two figures of a /proc/<pid>/status text ("VmRSS:    1234 kB" lines); a figure
// whose line is missing stays 0.
ResidentMemory parseResidentMemory(const std::string& status_text);
// This process's figures; both 0 where /proc/self/status cannot be read (not Linux).
ResidentMemory residentMemory();

}  // namespace valerant
