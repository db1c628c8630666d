// Helpers shared by the benchmarks.
#pragma once

#include <cstring>
#include <fstream>
#include <string>

namespace mesh4d::bench {

/// A field of /proc/self/status in kB ("VmRSS:", "VmHWM:"), or 0.
inline long status_kb(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::size_t n = std::strlen(field);
  while (std::getline(in, line))
    if (line.compare(0, n, field) == 0) return std::stol(line.substr(n + 1));
  return 0;
}

}  // namespace mesh4d::bench
