// An image as SubmitJob carries it: the raw labels (x fastest, little-endian, one byte per voxel
// when every label fits, two otherwise) and the ImageHeader that describes them, SHA-256
// included. The client encodes; the server checks the header before any data arrives, then
// decodes the data. Every failure is a ServiceError(invalid_argument, or resource_exhausted for
// absurd sizes) whose message says which field is wrong.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "domain/label_image.h"
#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::wire {

/// Fills `header` (dims, spacing, origin, label type, byte size, SHA-256) and returns the data.
std::string encode_upload(const domain::LabelImage4& image, v1::ImageHeader* header);

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

/// The same, the image not closed and its labels not yet checked: meshing with time caps
/// closes it after adding their ghost frames (refine/time_caps.h).
domain::LabelImage4 decode_unclosed(const v1::ImageHeader& header, std::string_view data,
                                    std::vector<std::string>* warnings,
                                    std::size_t extend_time_frames = 0);

}  // namespace mesh4d::wire
