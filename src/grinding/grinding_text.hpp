// Internal: number text for the grinding messages (6 significant digits,
// as the CLI prints numbers). Header-only.
#pragma once

#include <cstdio>
#include <string>

namespace chatter::grinding::detail {

inline std::string num(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

}  // namespace chatter::grinding::detail
