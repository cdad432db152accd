// Internal: the one error channel of the C API (chatter_c.cpp, grinding_c.cpp):
// the thread's last message and the wrapper that maps exceptions to status
// codes. Nothing propagates into C.
#pragma once

#include <exception>
#include <new>
#include <string>
#include <utility>

#include "chatter/chatter.h"
#include "chatter/error.hpp"

namespace chatter::capi {

/// The message of the last failed call on this thread (chatter_last_error).
std::string& last_error();

inline chatter_status fail(chatter_status s, std::string message) {
  last_error() = std::move(message);
  return s;
}

/// Runs `body`, mapping exceptions to status codes and the thread's message.
template <class F>
chatter_status guarded(F&& body) {
  last_error().clear();
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
