// Helpers shared by the benchmarks.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "mesh/mesh4.h"

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

/// A fingerprint of everything a mesh holds: its vertices (coordinates to the bit, kinds), its
/// pentatopes and labels, and its boundary tetrahedra, in their order (64-bit FNV-1a). Two builds
/// that give the same fingerprint on a row gave the same mesh; scripts/mesh_hashes lists them.
inline std::uint64_t mesh_fingerprint(const mesh::Mesh4& m) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  const auto mix = [&h](const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  };
  const auto mix_all = [&mix](const auto& items) {
    const std::uint64_t n = items.size();
    mix(&n, sizeof n);
    if (n > 0) mix(items.data(), n * sizeof items[0]);
  };
  mix_all(m.vertices);
  mix_all(m.vertex_kinds);
  mix_all(m.pentatopes);
  mix_all(m.labels);
  for (const mesh::BoundaryTetrahedron& b : m.boundary) {
    mix(b.vertices.data(), sizeof b.vertices);
    mix(&b.pentatope, sizeof b.pentatope);
    mix(&b.inner, sizeof b.inner);
    mix(&b.outer, sizeof b.outer);
  }
  return h;
}

/// Runs `work(0)` … `work(n − 1)` in n forked children at once (each a process of its own, as
/// independent jobs on one machine are) and returns their results in that order.
template <typename T, typename F>
std::vector<std::optional<T>> run_in_children_at_once(unsigned n, F&& work) {
  static_assert(std::is_trivially_copyable_v<T>);
  struct Child {
    pid_t pid = -1;
    int fd = -1;
  };
  std::vector<Child> children(n);
  for (unsigned i = 0; i < n; ++i) {
    int fd[2];
    if (pipe(fd) != 0) continue;
    const pid_t pid = fork();
    if (pid == 0) {
      close(fd[0]);
      const T result = work(i);
      const auto* bytes = reinterpret_cast<const char*>(&result);
      for (std::size_t at = 0; at < sizeof result;) {
        const ssize_t m = write(fd[1], bytes + at, sizeof result - at);
        if (m <= 0) _exit(1);
        at += static_cast<std::size_t>(m);
      }
      _exit(0);
    }
    close(fd[1]);
    if (pid < 0) {
      close(fd[0]);
      continue;
    }
    children[i] = {pid, fd[0]};
  }
  std::vector<std::optional<T>> out(n);
  for (unsigned i = 0; i < n; ++i) {
    if (children[i].pid < 0) continue;
    T result;
    auto* bytes = reinterpret_cast<char*>(&result);
    std::size_t at = 0;
    while (at < sizeof result) {
      const ssize_t m = read(children[i].fd, bytes + at, sizeof result - at);
      if (m <= 0) break;
      at += static_cast<std::size_t>(m);
    }
    close(children[i].fd);
    waitpid(children[i].pid, nullptr, 0);
    if (at == sizeof result) out[i] = result;
  }
  return out;
}

/// Runs `work` in a forked child, so that its peak memory is its own, and returns its result
/// (plain data, sent back through a pipe); nothing when the child failed or threw.
template <typename T, typename F>
std::optional<T> run_in_child(F&& work) {
  return run_in_children_at_once<T>(1, [&](unsigned) { return work(); })[0];
}

}  // namespace mesh4d::bench
