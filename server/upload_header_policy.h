// What the REST face takes of an image file's text header before ITK opens it.
// - The voxels must be in the file sent. NRRD's "data file" field and MetaImage's
//   ElementDataFile name other files, which ITK would open on the server's disk: a client could
//   have any file the server can read meshed and returned to it.
// - ITK's NRRD and MetaImage readers leak their state when loading fails, so a server that read
//   any header they parse would grow with each bad upload. A header is taken only when it is
//   plain text ending where both sides agree, and (NRRD) its data raw or gzip, so that the
//   engine's completeness check (domain/nrrd_data_check.h) can vouch for them beforehand.
#pragma once

#include <string>

namespace mesh4d::server {

/// Throws wire::ServiceError(invalid_argument), naming the rule, when the body, read as the
/// format its suffix names (".nrrd", ".nhdr", ".mha", ".mhd"), breaks one. Other suffixes pass.
void check_upload_header(const std::string& body, const std::string& suffix);

}  // namespace mesh4d::server
