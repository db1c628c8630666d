// The "Authorization: Bearer <token>" check shared by both faces. The scheme's name is
// case-insensitive (RFC 7235, 2.1: "bearer" and "BEARER" are the same); the token is not.
#pragma once

#include <string>
#include <string_view>

namespace mesh4d::server {

inline bool bearer_token_matches(std::string_view presented, const std::string& token) {
  constexpr std::string_view scheme = "bearer ";
  if (presented.size() != scheme.size() + token.size()) return false;
  for (std::size_t i = 0; i < scheme.size(); ++i) {
    const char c = presented[i];
    if ((c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c) != scheme[i]) return false;
  }
  return presented.substr(scheme.size()) == token;
}

}  // namespace mesh4d::server
