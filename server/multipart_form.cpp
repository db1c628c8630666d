#include "multipart_form.h"

#include <cctype>

#include "wire/service_error.h"

namespace mesh4d::server {
namespace {

[[noreturn]] void malformed(const std::string& what) {
  throw wire::ServiceError(wire::ErrorCode::invalid_argument, "the multipart body: " + what);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A header parameter's value (`key=value` or `key="value"`), "" when absent.
std::string parameter(std::string_view header, std::string_view key) {
  const std::string low = lower(header);
  for (std::size_t at = low.find(std::string(key) + "="); at != std::string::npos;
       at = low.find(std::string(key) + "=", at + 1)) {
    // A whole parameter name: after ';' or the start, not inside another name (filename/name).
    std::size_t before = at;
    while (before > 0 && header[before - 1] == ' ') --before;
    if (before != 0 && header[before - 1] != ';') continue;
    std::size_t from = at + key.size() + 1;
    if (from < header.size() && header[from] == '"') {
      const std::size_t end = header.find('"', from + 1);
      if (end == std::string_view::npos) malformed("an unterminated quoted " + std::string(key));
      return std::string(header.substr(from + 1, end - from - 1));
    }
    std::size_t end = header.find(';', from);
    if (end == std::string_view::npos) end = header.size();
    while (end > from && header[end - 1] == ' ') --end;
    return std::string(header.substr(from, end - from));
  }
  return "";
}

}  // namespace

std::vector<FormPart> parse_multipart(std::string_view content_type, std::string_view body) {
  const std::string boundary = parameter(content_type, "boundary");
  if (boundary.empty() || boundary.size() > 70)
    malformed("the boundary must be 1 to 70 characters (RFC 2046), not '" + boundary + "'");
  const std::string delimiter = "--" + boundary;
  // The first delimiter opens the body (anything before it is a preamble).
  std::size_t at = body.rfind(delimiter, 0) == 0 ? 0 : body.find("\r\n" + delimiter);
  if (at == std::string_view::npos) malformed("no part starts with the boundary");
  if (at != 0) at += 2;
  std::vector<FormPart> parts;
  while (true) {
    at += delimiter.size();
    if (body.substr(at, 2) == "--") return parts;  // the closing delimiter
    if (body.substr(at, 2) != "\r\n") malformed("a boundary line is not followed by CRLF");
    at += 2;
    const std::size_t headers_end = body.find("\r\n\r\n", at);
    if (headers_end == std::string_view::npos) malformed("a part's headers do not end");
    FormPart part;
    for (std::size_t line = at; line < headers_end + 2;) {
      const std::size_t eol = body.find("\r\n", line);
      const std::string_view header = body.substr(line, eol - line);
      if (lower(header.substr(0, 20)) == "content-disposition:") {
        part.name = parameter(header.substr(20), "name");
        part.filename = parameter(header.substr(20), "filename");
      }
      line = eol + 2;
    }
    const std::size_t content = headers_end + 4;
    const std::size_t next = body.find("\r\n" + delimiter, content);
    if (next == std::string_view::npos) malformed("it ends without its closing boundary");
    part.body = std::string(body.substr(content, next - content));
    if (part.name.empty()) malformed("a part has no name (Content-Disposition: form-data; name=)");
    parts.push_back(std::move(part));
    at = next + 2;
  }
}

}  // namespace mesh4d::server
