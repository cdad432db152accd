// Internal to the C API (src/capi/*.cpp): the handles' definitions and the
// exception-to-status guard every entry point runs its body in. Not
// installed.
#pragma once

#include <exception>
#include <memory>
#include <new>
#include <string>

#include "chatter/chatter.h"
#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/lobes.hpp"

struct chatter_model {
  chatter::Config config;
};

struct chatter_solver {
  std::unique_ptr<chatter::LobeSolver> solver;
};

namespace chatter::capi_detail {

/// Sets this thread's message (chatter_last_error) and returns `s`.
chatter_status fail(chatter_status s, std::string message);
/// Clears this thread's message.
void clear_error();

/// Runs `body`, mapping exceptions to status codes and the thread's message.
template <class F>
chatter_status guarded(F&& body) {
  clear_error();
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

}  // namespace chatter::capi_detail
