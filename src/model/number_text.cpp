// number_text (include/chatter/number_text.hpp).
#include "chatter/number_text.hpp"

#include <cstdio>

namespace chatter {

std::string number_text(double x, int significant) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", significant < 1 ? 1 : significant, x);
  return b;
}

}  // namespace chatter
