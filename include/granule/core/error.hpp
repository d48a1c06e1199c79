#pragma once
// Errors. Set-up mistakes throw InvalidParameter (a std::invalid_argument) whose message names
// where it happened, the parameter, the value and the valid range. A run that goes unstable
// throws InstabilityError (a std::runtime_error) with the step, particle and position; it is
// raised after the parallel loop, never inside it.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace granule {

/// A parameter outside its valid range, detected while a scene is set up.
class InvalidParameter : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The simulation became unstable (non-finite values, runaway overlap).
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file could not be read or written, or is not what it claims to be.
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
template <class T>
std::string to_text(const T& v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}
}  // namespace detail

/// Throws InvalidParameter("<where>: <name> = <value> is outside the valid range <range>")
/// unless `ok`. NaN always fails (callers write checks so that NaN makes `ok` false).
inline void require(bool ok, const std::string& where, const std::string& name, double value,
                    const std::string& range) {
  if (!ok || std::isnan(value)) {
    throw InvalidParameter(where + ": " + name + " = " + detail::to_text(value) +
                           " is outside the valid range " + range);
  }
}

/// Checks lo < value < hi style conditions with readable ranges.
inline void require_positive(double value, const std::string& where, const std::string& name) {
  require(value > 0.0 && std::isfinite(value), where, name, value, "(0, inf)");
}
inline void require_non_negative(double value, const std::string& where, const std::string& name) {
  require(value >= 0.0 && std::isfinite(value), where, name, value, "[0, inf)");
}
inline void require_finite(double value, const std::string& where, const std::string& name) {
  require(std::isfinite(value), where, name, value, "finite numbers");
}

}  // namespace granule
