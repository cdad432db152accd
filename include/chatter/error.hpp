// Error channels (see docs/architecture.md):
//  - bad user input (a config, an option, a file) throws chatter::InputError,
//    whose message names the file, the key and the rule, so a machinist can act;
//  - a numerical failure that is not the user's fault throws
//    chatter::NumericalError;
//  - expected outcomes (no instability below the searched depth) come back in
//    result objects, never as exceptions.
// Only main() turns exceptions into exit codes (2 for InputError, 1 otherwise).
#pragma once

#include <stdexcept>
#include <string>

namespace chatter {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace chatter
