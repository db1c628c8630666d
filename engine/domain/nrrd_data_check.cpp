#include "domain/nrrd_data_check.h"

#include <zlib.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A NRRD header is text up to the first empty line; the fields that place the data.
struct NrrdLayout {
  std::uint64_t data_offset = 0;  // 0: no complete header in the file's head
  std::map<std::string, std::string> fields;
};

NrrdLayout read_layout(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(1 << 16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  NrrdLayout layout;
  if (head.rfind("NRRD", 0) != 0) return layout;
  std::size_t at = 0;
  while (at < head.size()) {
    const std::size_t end = head.find('\n', at);
    if (end == std::string::npos) return layout;
    std::string line = head.substr(at, end - at);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    at = end + 1;
    if (line.empty()) {
      layout.data_offset = at;
      return layout;
    }
    if (line[0] == '#') continue;
    if (const std::size_t colon = line.find(':'); colon != std::string::npos) {
      // NrrdIO reads field names and encodings regardless of case.
      std::string value = lower(line.substr(colon + 1));
      value.erase(0, value.find_first_not_of(" \t"));
      value.erase(value.find_last_not_of(" \t") + 1);
      layout.fields[lower(line.substr(0, colon))] = value;
    }
  }
  return layout;
}

// Bytes that the gzip stream from `offset` inflates to, counted up to `limit`.
std::uint64_t inflated_bytes(const std::string& path, std::uint64_t offset, std::uint64_t limit,
                             bool* corrupt) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) return 0;  // 15 + 32: gzip or zlib header
  std::vector<unsigned char> input(1 << 16), output(1 << 16);
  std::uint64_t total = 0;
  int status = Z_OK;
  while (total < limit && status != Z_STREAM_END) {
    if (z.avail_in == 0) {
      in.read(reinterpret_cast<char*>(input.data()), static_cast<std::streamsize>(input.size()));
      z.avail_in = static_cast<unsigned>(in.gcount());
      z.next_in = input.data();
      if (z.avail_in == 0) break;
    }
    z.next_out = output.data();
    z.avail_out = static_cast<unsigned>(output.size());
    status = inflate(&z, Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END) {
      *corrupt = status != Z_BUF_ERROR;
      break;
    }
    total += output.size() - z.avail_out;
  }
  inflateEnd(&z);
  return total;
}

}  // namespace

void check_nrrd_data_complete(const std::string& path, std::uint64_t voxel_bytes) {
  const NrrdLayout layout = read_layout(path);
  if (layout.data_offset == 0) return;
  const auto& f = layout.fields;
  if (f.count("data file") || f.count("datafile") || f.count("line skip") || f.count("lineskip") ||
      f.count("byte skip") || f.count("byteskip"))
    return;
  const auto encoding = f.find("encoding");
  if (encoding == f.end()) return;
  std::uint64_t held = 0;
  if (encoding->second == "raw") {
    std::error_code error;
    const std::uint64_t size = std::filesystem::file_size(path, error);
    if (error) return;
    held = size - layout.data_offset;
  } else if (encoding->second == "gzip" || encoding->second == "gz") {
    bool corrupt = false;
    held = inflated_bytes(path, layout.data_offset, voxel_bytes, &corrupt);
    if (corrupt) throw ImageError(path + ": the NRRD's gzip data are corrupt");
  } else {
    return;
  }
  if (held < voxel_bytes) {
    std::ostringstream m;
    m << path << ": the NRRD's data end early: " << held << " bytes of the header's "
      << voxel_bytes;
    throw ImageError(m.str());
  }
}

}  // namespace mesh4d::domain
