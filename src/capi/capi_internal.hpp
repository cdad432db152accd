// Internal to the C API (src/capi/*.cpp; not installed): the handles'
// definitions and the one error channel every entry point runs its body in
// (the thread's last message and the wrapper that maps exceptions to status
// codes: nothing propagates into C).
#pragma once

#include <exception>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "chatter/chatter.h"
#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/lobes.hpp"
#include "chatter/process.hpp"
#include "chatter/records.hpp"

struct chatter_model {
  chatter::Config config;
};

struct chatter_solver {
  std::unique_ptr<chatter::LobeSolver> solver;
  std::string method;            // "auto" resolved
  chatter::Process process;      // for the point report's frequencies
  chatter::RecordSource source;  // warnings and notes for the point record
};

namespace chatter::capi {

/// The message of the last failed call on this thread (chatter_last_error).
std::string& last_error();

/// The plausibility warnings of the last call's numeric arguments on this
/// thread (chatter_last_warning): cleared by every call.
std::vector<std::string>& last_warnings();

/// Names each argument whose value lies outside its usual band (the bands of
/// the CLI flags and Python keywords: `unusual_arguments`, usual_bands.hpp)
/// in the thread's warnings; names as the CLI flag (`rpm`, `depth_mm`, ...).
void warn_unusual(const std::vector<std::pair<std::string, double>>& arguments);

/// A record's source with the thread's argument warnings after the config's
/// (what the JSON records of the C API carry in `warnings`).
inline chatter::RecordSource with_argument_warnings(chatter::RecordSource source) {
  for (const std::string& w : last_warnings()) source.warnings.push_back(w);
  return source;
}

inline chatter_status fail(chatter_status s, std::string message) {
  last_error() = std::move(message);
  last_warnings().clear();
  return s;
}

/// Runs `body`, mapping exceptions to status codes and the thread's message.
template <class F>
chatter_status guarded(F&& body) {
  last_error().clear();
  last_warnings().clear();
  try {
    body();
    return CHATTER_OK;
  } catch (const chatter::InputError& e) {
    return fail(CHATTER_INPUT_ERROR, e.what());
  } catch (const std::bad_alloc&) {
    return fail(CHATTER_INTERNAL_ERROR, "out of memory");
  } catch (const std::exception& e) {
    return fail(CHATTER_INTERNAL_ERROR, e.what());
  } catch (...) {
    return fail(CHATTER_INTERNAL_ERROR, "unknown internal error");
  }
}

}  // namespace chatter::capi
