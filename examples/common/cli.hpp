#pragma once
// The examples' command lines, on CLI11 (Debian: libcli11-dev, header-only). Only the examples
// use it; the library does not.
//
// CLI11's own conversions are lenient where a typo should be caught: an unsigned option takes
// "-5" and wraps it, "010" is read as octal and "inf" as a number. So every number here is read
// by from_chars, the whole text in decimal, finite, then checked against its range, and each
// error names the option and the value. run() turns what can go wrong into an exit code:
//   0  done, or --help
//   1  the run failed: a granule error (InvalidParameter, InstabilityError, IoError) or another
//      exception, with its message
//   2  a bad command line: an unknown option, a malformed number, a value out of its range
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

#include <granule/core/error.hpp>

namespace granule::examples::cli {

inline constexpr int exit_failed = 1;  ///< the run failed
inline constexpr int exit_usage = 2;   ///< a bad command line

/// A command line that parses but does not make sense as a whole (options that exclude each
/// other, a value that contradicts another): exit code 2, like a parse error.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The values an option accepts: an interval, each end open or closed, infinite by default.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_closed = false;
  bool hi_closed = false;

  bool contains(double v) const {
    return (lo_closed ? v >= lo : v > lo) && (hi_closed ? v <= hi : v < hi);
  }
  /// In the library's notation: "(0, inf)", "[1, 64]".
  std::string text() const {
    auto end = [](double x) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%.12g", x);
      return std::isinf(x) ? std::string(x < 0 ? "-inf" : "inf") : std::string(buf);
    };
    return std::string(lo_closed ? "[" : "(") + end(lo) + ", " + end(hi) + (hi_closed ? "]" : ")");
  }
};
inline Range any() { return {}; }
inline Range positive() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
inline Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
inline Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, false}; }
inline Range closed(double lo, double hi) { return {lo, hi, true, true}; }

namespace detail {

// A leading '+' is allowed before a digit or a point ("+1", "+.5"), never before a sign.
inline std::string_view drop_plus(std::string_view s) {
  if (s.size() > 1 && s.front() == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  return s;
}

inline std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%g", v);
  return buf;
}

}  // namespace detail

/// The whole of `text` as a finite number in decimal or exponent notation ("2e-3", "-0.5"),
/// or nothing ("1.5x", "1.5.5", "abc", "", " 1", "inf", "nan", "0x10", "1e999").
inline std::optional<double> parse_real(std::string_view text) {
  text = detail::drop_plus(text);
  if (text.empty() || text.front() == '+') return std::nullopt;
  double v = 0.0;
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v, std::chars_format::general);
  if (ec != std::errc() || p != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// The whole of `text` as a decimal integer of type T, or nothing ("1.5", "1e3", "0x10", "",
/// a value T cannot hold). A negative text for an unsigned T is returned as nothing too; the
/// option adders report it as out of range.
template <class T>
std::optional<T> parse_integer(std::string_view text) {
  static_assert(std::is_integral_v<T>);
  text = detail::drop_plus(text);
  if (text.empty() || text.front() == '+') return std::nullopt;
  T v{};
  const char* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, v, 10);
  if (ec != std::errc() || p != end) return std::nullopt;
  return v;
}

/// A real number for `--name`, checked against `range`; throws CLI::ValidationError naming the
/// option and the value.
inline double to_real(const std::string& name, const std::string& text, const Range& range) {
  const auto v = parse_real(text);
  if (!v) throw CLI::ValidationError(name + " = '" + text + "' is not a number");
  if (!range.contains(*v))
    throw CLI::ValidationError(name + " = " + text + " is outside the valid range " + range.text());
  return *v;
}

/// A whole number in [lo, hi] for `--name`; throws CLI::ValidationError naming the option and
/// the value ("-1" for an unsigned option is out of range, not malformed).
template <class T>
T to_whole(const std::string& name, const std::string& text, T lo, T hi) {
  auto out_of_range = [&] {
    return CLI::ValidationError(name + " = " + text + " is outside the valid range [" + std::to_string(lo) +
                                ", " + std::to_string(hi) + "]");
  };
  const auto v = parse_integer<T>(text);
  if (!v) {
    const std::string_view t = detail::drop_plus(text);
    const std::size_t first = !t.empty() && t.front() == '-' ? 1 : 0;
    const bool digits = t.size() > first && t.find_first_not_of("0123456789", first) == std::string_view::npos;
    if (digits) throw out_of_range();  // a whole number, but not one that T holds
    throw CLI::ValidationError(name + " = '" + text + "' is not a whole number");
  }
  if (*v < lo || *v > hi) throw out_of_range();
  return *v;
}

/// The comma-separated numbers of `text` ("0,1,2"), each checked against `range`.
inline std::vector<double> to_real_list(const std::string& name, const std::string& text, const Range& range) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto v = parse_real(item);
    if (!v)
      throw CLI::ValidationError(name + " = '" + text + "': '" + item + "' is not a number (expected a,b,...)");
    if (!range.contains(*v))
      throw CLI::ValidationError(name + " = " + text + ": " + item + " is outside the valid range " + range.text());
    out.push_back(*v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

/// CLI11's help with the option descriptions wrapped to fit 100 columns (CLI11 2.1 does not wrap).
class WrappingFormatter : public CLI::Formatter {
 public:
  static constexpr std::size_t width = 100;
  std::string make_option_desc(const CLI::Option* opt) const override {
    const std::string text = CLI::Formatter::make_option_desc(opt);
    const std::size_t room = width > get_column_width() + 20 ? width - get_column_width() : 20;
    std::string out, line;
    std::size_t start = 0;
    while (start <= text.size()) {
      std::size_t end = text.find(' ', start);
      if (end == std::string::npos) end = text.size();
      const std::string word = text.substr(start, end - start);
      if (!line.empty() && line.size() + 1 + word.size() > room) {
        out += line + "\n";
        line.clear();
      }
      line += (line.empty() ? "" : " ") + word;
      start = end + 1;
    }
    return out + line;
  }
};

/// Sets up `app` as every example wants it: repeated options keep the last value (a script may
/// give a default first and let its caller's arguments override it, as the former hand-written
/// parsers allowed), and descriptions wrapped beside a column wide enough for the option names.
inline void configure(CLI::App& app) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  auto formatter = std::make_shared<WrappingFormatter>();
  formatter->column_width(36);
  app.formatter(formatter);
}

/// `--name X`: a real number in `range` stored into `target`; --help shows target's value at
/// this call as the default unless `show_default` is false.
inline CLI::Option* add_real(CLI::App& app, const std::string& name, double& target, const std::string& help,
                             const Range& range = any(), bool show_default = true) {
  CLI::Option* o = app.add_option_function<std::string>(
      name, [&target, name, range](const std::string& s) { target = to_real(name, s, range); }, help);
  o->type_name("X");
  if (show_default) o->default_str(detail::number_text(target));
  return o;
}

/// `--name N`: a whole number in [lo, hi] stored into `target` (default shown as for add_real).
template <class T>
CLI::Option* add_whole(CLI::App& app, const std::string& name, T& target, const std::string& help, T lo,
                       T hi = std::numeric_limits<T>::max(), bool show_default = true) {
  CLI::Option* o = app.add_option_function<std::string>(
      name, [&target, name, lo, hi](const std::string& s) { target = to_whole<T>(name, s, lo, hi); }, help);
  o->type_name("N");
  if (show_default) o->default_str(std::to_string(target));
  return o;
}

/// `--name a,b,...`: comma-separated real numbers, each in `range`; exactly `count` of them
/// unless count is 0.
inline CLI::Option* add_real_list(CLI::App& app, const std::string& name, std::vector<double>& target,
                                  const std::string& help, const Range& range = any(), std::size_t count = 0) {
  CLI::Option* o = app.add_option_function<std::string>(
      name,
      [&target, name, range, count](const std::string& s) {
        auto v = to_real_list(name, s, range);
        if (count != 0 && v.size() != count)
          throw CLI::ValidationError(name + " = '" + s + "' has " + std::to_string(v.size()) + " values, expected " +
                                     std::to_string(count));
        target = std::move(v);
      },
      help);
  o->type_name("a,b,...");
  return o;
}

/// `--name TEXT` stored into `target` (a std::string or a path); an empty value is refused.
template <class T>
CLI::Option* add_text(CLI::App& app, const std::string& name, T& target, const std::string& help) {
  CLI::Option* o = app.add_option_function<std::string>(
      name,
      [&target, name](const std::string& s) {
        if (s.empty()) throw CLI::ValidationError(name + " = '': needs a non-empty value");
        target = s;
      },
      help);
  o->type_name("TEXT");
  return o;
}

/// Parses argv into the options of `app`, then returns body(). Every failure becomes a message
/// on stderr that starts with the program's name, and an exit code (see the top of this file).
template <class Body>
int run(CLI::App& app, int argc, char** argv, Body&& body) {
  const std::string program = app.get_name();
  auto fail = [&](const char* what, int code, bool hint) {
    std::fprintf(stderr, "%s: %s%s\n", program.c_str(), what, hint ? " (see --help)" : "");
    return code;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help
    return fail(e.what(), exit_usage, true);
  }
  try {
    return body();
  } catch (const UsageError& e) {
    return fail(e.what(), exit_usage, true);
  } catch (const CLI::ParseError& e) {
    return fail(e.what(), exit_usage, true);
  } catch (const std::exception& e) {
    // granule's errors (InvalidParameter, InstabilityError, IoError) say where and what.
    return fail(e.what(), exit_failed, false);
  }
}

}  // namespace granule::examples::cli
