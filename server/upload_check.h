// Checks an upload against its header before a job is acknowledged: dims, spacing and origin,
// label type, byte size, checksum, and that the labels can be meshed. Every failure is a
// ServiceError(invalid_argument) whose message says which field is wrong.
#pragma once

#include <string_view>

#include "domain/label_image.h"
#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::server {

/// Bytes per voxel of a label type; throws ServiceError for LABEL_TYPE_UNSPECIFIED or unknown.
std::size_t label_bytes(v1::LabelType type);

/// The header alone (before any data arrives): returns the byte size it implies.
std::uint64_t check_header(const v1::ImageHeader& header);

/// The decoded image, closed (validate_and_close) with its warnings: after check_header, checks
/// the data's size and SHA-256 and the labels themselves. With `extend_time_frames`, the end
/// frames are repeated (domain::extend_time) before the image is closed.
domain::LabelImage4 decode_upload(const v1::ImageHeader& header, std::string_view data,
                                  std::vector<std::string>* warnings,
                                  std::size_t extend_time_frames = 0);

}  // namespace mesh4d::server
