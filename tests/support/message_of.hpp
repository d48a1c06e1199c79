#pragma once
// The message of an expected exception, for tests that check what an error says.
#include <exception>
#include <string>

namespace granule::test {

/// The message of the exception of type E thrown by f(), or a text saying what happened instead
/// (another exception, or none), so that a failing CHECK_THAT shows the cause.
template <class E, class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("<other exception: ") + e.what() + ">";
  }
  return "<no exception>";
}

}  // namespace granule::test
