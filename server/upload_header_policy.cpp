#include "upload_header_policy.h"

#include <algorithm>
#include <cctype>
#include <string_view>

#include "wire/service_error.h"

namespace mesh4d::server {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

[[noreturn]] void refuse(const std::string& what) {
  throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                           what + ": an upload must carry its voxels in the one file sent");
}

[[noreturn]] void refuse_header(const std::string& format, const std::string& what) {
  throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                           "the " + format + " header " + what +
                               "; send it as NIfTI (.nii, .nii.gz), or as a " + format +
                               " file with a plain-text header and its voxels attached");
}

bool plain_text(std::string_view header) {
  return std::all_of(header.begin(), header.end(), [](unsigned char c) {
    return (c >= 0x20 && c < 0x7f) || c == '\n' || c == '\r' || c == '\t';
  });
}

// The checks are by substring over the whole header, not by parsing it as ITK's readers do:
// what they take for a field name (NUL bytes, case, separators) is theirs to decide, and any
// header that mentions a data file at all is refused.

// A NRRD header ends at its first empty line.
void check_nrrd(std::string_view body) {
  std::size_t end = body.find("\n\n");
  if (const std::size_t crlf = body.find("\n\r\n"); crlf < end) end = crlf;
  if (end == std::string_view::npos) refuse_header("NRRD", "has no empty line that ends it");
  if (end > 60000) refuse_header("NRRD", "is longer than 60,000 bytes");
  if (!plain_text(body.substr(0, end))) refuse_header("NRRD", "is not plain text");
  const std::string header = lower(body.substr(0, end));
  if (header.find("data file") != std::string::npos || header.find("datafile") != std::string::npos)
    refuse("the NRRD header names a data file (\"data file:\")");
  if (header.find("line skip") != std::string::npos ||
      header.find("lineskip") != std::string::npos ||
      header.find("byte skip") != std::string::npos || header.find("byteskip") != std::string::npos)
    refuse_header("NRRD", "skips lines or bytes before the data");
  const std::size_t encoding = header.find("\nencoding:");
  const std::string_view value =
      encoding == std::string::npos
          ? std::string_view()
          : trimmed(std::string_view(header).substr(
                encoding + 11, header.find('\n', encoding + 1) - encoding - 11));
  if (value != "raw" && value != "gzip" && value != "gz")
    refuse_header("NRRD", "gives an encoding other than raw or gzip");
}

// A MetaImage header ends with its ElementDataFile field; LOCAL means the voxels follow. It must
// be plain text up to a line that says exactly that.
void check_meta_image(std::string_view body) {
  const std::size_t key = lower(body.substr(0, 1 << 16)).find("elementdatafile");
  if (key == std::string::npos) refuse("the MetaImage header has no ElementDataFile = LOCAL");
  const std::size_t line_start =
      body.rfind('\n', key) == std::string_view::npos ? 0 : body.rfind('\n', key) + 1;
  const std::size_t line_end = std::min(body.find('\n', key), body.size());
  const std::string_view line = trimmed(body.substr(line_start, line_end - line_start));
  const std::size_t separator = line.find_first_of("=:");
  // MetaIO takes the value's case as it is: "lOCAL" is a file name to it.
  const std::string_view value =
      separator == std::string_view::npos ? "" : trimmed(line.substr(separator + 1));
  const bool local = separator != std::string_view::npos &&
                     lower(trimmed(line.substr(0, separator))) == "elementdatafile" &&
                     (value == "LOCAL" || value == "Local" || value == "local");
  if (!plain_text(body.substr(0, line_end))) refuse_header("MetaImage", "is not plain text");
  if (!local) refuse("the MetaImage header's ElementDataFile is not LOCAL");
}

}  // namespace

void check_upload_header(const std::string& body, const std::string& suffix) {
  if (suffix == ".nrrd" || suffix == ".nhdr")
    check_nrrd(body);
  else if (suffix == ".mha" || suffix == ".mhd")
    check_meta_image(body);
}

}  // namespace mesh4d::server
