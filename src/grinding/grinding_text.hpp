// Internal: number text for the grinding messages (6 significant digits,
// as the CLI prints numbers). Header-only.
#pragma once

#include <string>

#include "chatter/number_text.hpp"

namespace chatter::grinding::detail {

inline std::string num(double x) {
  return number_text(x);
}

}  // namespace chatter::grinding::detail
