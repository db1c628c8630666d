// A NRRD file's data, checked against its header before ITK reads them. ITK's NRRD reader
// (NrrdIO) leaks its parse state whenever loading fails, so data that end early must be refused
// before it is called; a server that reads uploads would otherwise grow with every bad one.
#pragma once

#include <cstdint>
#include <string>

namespace mesh4d::domain {

/// For a NRRD file with attached raw or gzip data: throws ImageError when the data hold fewer
/// than `voxel_bytes` bytes (gzip data are inflated only that far). Other files, detached data
/// and other encodings are left to the reader.
void check_nrrd_data_complete(const std::string& path, std::uint64_t voxel_bytes);

}  // namespace mesh4d::domain
