// The public API throws rtd::Error (and std::bad_alloc) only. Entry points that run code which
// could throw something else (the standard library, oneTBB, a driver) call it through guarded().
#pragma once
#include <exception>
#include <new>
#include <string>

#include "rtd/error.h"

namespace rtd {

/// Returns fn(), letting rtd::Error and std::bad_alloc through and turning any other exception
/// into rtd::Error("<what>: internal error: ..."), which names the call it escaped from.
template <class F> decltype(auto) guarded(const char* what, F&& fn) {
  try {
    return fn();
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(std::string(what) + ": internal error: " + e.what());
  }
}

}  // namespace rtd
