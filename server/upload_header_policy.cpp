#include "upload_header_policy.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <string_view>
#include <vector>

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

// Printable ASCII, tabs and line ends. A carriage return only ends a line (before '\n'): the
// readers split lines on a lone one too, or keep it in a value, where these checks would not.
bool plain_text(std::string_view header) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(header[i]);
    const bool line_end = c == '\r' && (i + 1 == header.size() || header[i + 1] == '\n');
    if (!((c >= 0x20 && c < 0x7f) || c == '\n' || c == '\t' || line_end)) return false;
  }
  return true;
}

// The checks are by substring over the whole header, not by parsing it as ITK's readers do:
// what they take for a field name (NUL bytes, case, separators) is theirs to decide, and any
// header that mentions a data file at all is refused.

// Space-separated tokens of a value.
std::vector<std::string_view> tokens(std::string_view value) {
  std::vector<std::string_view> out;
  while (!(value = trimmed(value)).empty()) {
    const std::size_t end = std::min(value.find_first_of(" \t"), value.size());
    out.push_back(value.substr(0, end));
    value.remove_prefix(end);
  }
  return out;
}

bool number(std::string_view token, bool positive_integer = false) {
  if (token.empty() || token.size() > 40) return false;
  const std::string text(token);
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(x)) return false;
  return !positive_integer ||
         (text.find_first_not_of("0123456789") == std::string::npos && x >= 1 && x < 1e12);
}

// "(x,y,z)" with `n` numbers.
bool vector_token(std::string_view token, std::size_t n) {
  if (token.size() < 2 || token.front() != '(' || token.back() != ')') return false;
  token = token.substr(1, token.size() - 2);
  std::size_t count = 0;
  for (;;) {
    const std::size_t comma = std::min(token.find(','), token.size());
    if (!number(trimmed(token.substr(0, comma)))) return false;
    ++count;
    if (comma == token.size()) break;
    token.remove_prefix(comma + 1);
  }
  return count == n;
}

// NrrdIO leaks whatever it has parsed when a header fails, so the fields it would parse are
// checked here first: only those a label volume needs, each with a value of its form, and no
// key:=value pairs.
void check_nrrd_fields(std::string_view header) {
  static const std::set<std::string_view> kTypes = {
      "uint8",  "uchar",  "unsigned char",  "int8",  "signed char", "char",
      "uint16", "ushort", "unsigned short", "int16", "short",       "signed short",
      "uint32", "uint",   "unsigned int",   "int32", "int",         "signed int",
      "uint64", "int64",  "float",          "double"};
  // Each space with its dimension: ITK takes a space only as wide as the image.
  static const std::map<std::string_view, std::size_t> kSpaces = {
      {"right-anterior-superior", 3},
      {"RAS", 3},
      {"left-anterior-superior", 3},
      {"LAS", 3},
      {"left-posterior-superior", 3},
      {"LPS", 3},
      {"right-anterior-superior-time", 4},
      {"RAST", 4},
      {"left-anterior-superior-time", 4},
      {"LAST", 4},
      {"left-posterior-superior-time", 4},
      {"LPST", 4},
      {"scanner-xyz", 3},
      {"scanner-xyz-time", 4},
      {"3D-right-handed", 3},
      {"3D-left-handed", 3},
      {"3D-right-handed-time", 4},
      {"3D-left-handed-time", 4}};
  static const std::set<std::string_view> kKinds = {"domain", "space", "time", "list",
                                                    "scalar", "none",  "???"};
  static const std::set<std::string_view> kCenters = {"cell", "node", "none", "???"};
  std::size_t dimension = 0, space_dimension = 3;
  std::map<std::string, std::string_view> fields;
  std::size_t at = header.find('\n') + 1;  // after the magic line
  if (header.rfind("NRRD000", 0) != 0 || at == 0)
    refuse_header("NRRD", "does not start with its magic (NRRD0001 to NRRD0005)");
  while (at < header.size()) {
    const std::size_t end = std::min(header.find('\n', at), header.size());
    std::string_view line = header.substr(at, end - at);
    at = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos || line.substr(colon).rfind(":=", 0) == 0)
      refuse_header("NRRD", "has a line that is not \"field: value\" (key:=value pairs included)");
    const std::string field(line.substr(0, colon));
    if (fields.count(field)) refuse_header("NRRD", "gives \"" + field + "\" twice");
    fields[field] = trimmed(line.substr(colon + 1));
  }
  const auto bad = [](const std::string& field) {
    refuse_header("NRRD", "has a \"" + field + "\" field that is not read here or not of its form");
  };
  for (const char* needed : {"type", "dimension", "sizes", "encoding"})
    if (!fields.count(needed)) bad(needed);
  const std::string_view d = fields["dimension"];
  if (d.size() != 1 || d[0] < '1' || d[0] > '4') bad("dimension");
  dimension = std::size_t(d[0] - '0');
  if (fields.count("space dimension")) {
    const std::string_view sd = fields["space dimension"];
    if (sd.size() != 1 || sd[0] < '1' || sd[0] > '4') bad("space dimension");
    space_dimension = std::size_t(sd[0] - '0');
  }
  if (fields.count("space")) {
    const auto space = kSpaces.find(fields["space"]);
    if (space == kSpaces.end()) bad("space");
    space_dimension = space->second;
  }
  if ((fields.count("space") || fields.count("space dimension")) && space_dimension != dimension)
    refuse_header("NRRD", "gives a space of another dimension than the image's");
  for (const auto& [field, value] : fields) {
    const auto t = tokens(value);
    const auto all = [&](auto ok) { return std::all_of(t.begin(), t.end(), ok); };
    bool fine = true;
    if (field == "type") {
      fine = kTypes.count(value) > 0;
    } else if (field == "sizes") {
      fine = t.size() == dimension && all([](auto x) { return number(x, true); });
    } else if (field == "spacings" || field == "thicknesses" || field == "axis mins" ||
               field == "axis maxs") {
      fine = t.size() == dimension && all([](auto x) { return x == "nan" || number(x); });
    } else if (field == "endian") {
      fine = value == "little" || value == "big";
    } else if (field == "space") {
      fine = true;  // checked above
    } else if (field == "space directions") {
      fine = t.size() == dimension && all([&](auto x) { return vector_token(x, space_dimension); });
    } else if (field == "space origin") {
      fine = t.size() == 1 && vector_token(t[0], space_dimension);
    } else if (field == "kinds") {
      fine = t.size() == dimension && all([](auto x) { return kKinds.count(x) > 0; });
    } else if (field == "centers" || field == "centerings") {
      fine = t.size() == dimension && all([](auto x) { return kCenters.count(x) > 0; });
    } else if (field == "content" || field == "space dimension" || field == "dimension" ||
               field == "encoding") {
      fine = true;
    } else {
      fine = false;
    }
    if (!fine) bad(field);
  }
}

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
  constexpr std::string_view kEncoding = "\nencoding:";
  std::string_view value;
  if (const std::size_t at = header.find(kEncoding); at != std::string::npos) {
    const std::size_t start = at + kEncoding.size();  // within the header: it ends with ':'
    value = trimmed(std::string_view(header).substr(start, header.find('\n', start) - start));
  }
  if (value != "raw" && value != "gzip" && value != "gz")
    refuse_header("NRRD", "gives an encoding other than raw or gzip");
  check_nrrd_fields(body.substr(0, end));
}

// A MetaImage header ends with its ElementDataFile field; LOCAL means the voxels follow. MetaIO
// parses malformed headers past their end (a misspelt key sent it reading beyond its buffer), so
// every line before the voxels must be a field it knows, spelt as it spells it, with a value of
// the kind that field takes.
void check_meta_image(std::string_view body) {
  static const std::map<std::string_view, const char*> kFields = {
      // field: the characters its value may hold ("" for any plain text)
      {"ObjectType", ""},
      {"ObjectSubType", ""},
      {"Comment", ""},
      {"Name", ""},
      {"Modality", ""},
      {"AnatomicalOrientation", ""},
      {"DistanceUnits", ""},
      {"NDims", "0123456789 "},
      {"DimSize", "0123456789 "},
      {"ElementNumberOfChannels", "0123456789 "},
      {"CompressedDataSize", "0123456789 "},
      {"ElementSpacing", "0123456789+-.eE "},
      {"ElementSize", "0123456789+-.eE "},
      {"Offset", "0123456789+-.eE "},
      {"Position", "0123456789+-.eE "},
      {"Origin", "0123456789+-.eE "},
      {"TransformMatrix", "0123456789+-.eE "},
      {"Orientation", "0123456789+-.eE "},
      {"Rotation", "0123456789+-.eE "},
      {"CenterOfRotation", "0123456789+-.eE "},
      {"ElementMin", "0123456789+-.eE "},
      {"ElementMax", "0123456789+-.eE "},
      {"BinaryData", "TrueFalse"},
      {"BinaryDataByteOrderMSB", "TrueFalse"},
      {"ElementByteOrderMSB", "TrueFalse"},
      {"CompressedData", "TrueFalse"},
      {"ElementType", "MET_UCHARSORTINGLFDB"},
  };
  std::size_t at = 0;
  for (;;) {
    const std::size_t end = body.find('\n', at);
    if (end == std::string_view::npos || end - at > 4096)
      refuse_header("MetaImage", "has no line ElementDataFile = LOCAL");
    std::string_view line = body.substr(at, end - at);
    at = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!plain_text(line) || line.find('\r') != std::string_view::npos)
      refuse_header("MetaImage", "is not plain text");
    const std::size_t separator = line.find_first_of("=:");
    if (separator == std::string_view::npos)
      refuse_header("MetaImage", "has a line that is not \"Field = value\"");
    const std::string_view key = trimmed(line.substr(0, separator));
    const std::string_view value = trimmed(line.substr(separator + 1));
    if (key == "ElementDataFile") {
      // MetaIO takes the value's case as it is: "lOCAL" is a file name to it.
      if (value != "LOCAL" && value != "Local" && value != "local")
        refuse("the MetaImage header's ElementDataFile is not LOCAL");
      break;
    }
    const auto field = kFields.find(key);
    if (field == kFields.end())
      refuse_header("MetaImage", "has a field \"" + std::string(key) + "\" that is not read here");
    const std::string_view allowed = field->second;
    if (!allowed.empty() && value.find_first_not_of(allowed) != std::string_view::npos)
      refuse_header("MetaImage", "gives " + std::string(key) + " a value it cannot take");
    // MetaIO reads as many numbers per field as NDims says, and makes as many channels as asked.
    if ((key == "NDims" || key == "ElementNumberOfChannels") &&
        (value.empty() || value.size() > 1 || value[0] < '1' || value[0] > '4'))
      refuse_header("MetaImage", "gives " + std::string(key) + " a value outside 1 to 4");
    if (key == "CompressedDataSize" &&
        std::strtoull(std::string(value).c_str(), nullptr, 10) > body.size())
      refuse_header("MetaImage", "announces more compressed data than it holds");
  }
}

}  // namespace

void check_upload_header(const std::string& body, const std::string& suffix) {
  if (suffix == ".nrrd" || suffix == ".nhdr")
    check_nrrd(body);
  else if (suffix == ".mha" || suffix == ".mhd")
    check_meta_image(body);
}

}  // namespace mesh4d::server
