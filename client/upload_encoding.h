// The inverse of the server's decode_upload: an engine image as the raw label bytes the API
// carries (x fastest, little-endian, uint8 when every label fits, uint16 otherwise) and the
// ImageHeader describing them, SHA-256 included. Shared by the client, tests and benchmarks.
#pragma once

#include <string>

#include "domain/label_image.h"
#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::client {

/// Fills `header` (dims, spacing, origin, label type, byte size, SHA-256) and returns the data.
std::string encode_upload(const domain::LabelImage4& image, v1::ImageHeader* header);

}  // namespace mesh4d::client
