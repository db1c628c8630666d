// Durable writes for the job store: a file is written to a temporary name, flushed to disk,
// renamed over its final name and the directory entry flushed too, so that after a crash the
// file is either the old one or the whole new one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace mesh4d::server {

/// Throws std::system_error when the disk refuses.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

/// Reads a whole file; throws std::system_error when it cannot.
std::vector<std::uint8_t> read_whole_file(const std::filesystem::path& path);

/// Flushes a directory's entries (after a rename or a new subdirectory).
void sync_directory(const std::filesystem::path& dir);

}  // namespace mesh4d::server
