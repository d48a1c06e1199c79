#pragma once
// The fields of one line of the studies' CSV files: text fields (commit, machine, descriptions)
// are quoted so that they may hold commas, and a reader splits the line back into fields.
#include <string>
#include <vector>

namespace granule::examples {

/// `s` in double quotes, inner quotes doubled (RFC 4180).
inline std::string csv_quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

/// The fields of one CSV line, quotes removed.
inline std::vector<std::string> csv_split(const std::string& line) {
  std::vector<std::string> out(1);
  bool in_quotes = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (!in_quotes) {
      if (c == '"') in_quotes = true;
      else if (c == ',') out.emplace_back();
      else out.back() += c;
    } else if (c != '"') {
      out.back() += c;
    } else if (i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';  // a doubled quote inside a quoted field
      ++i;
    } else {
      in_quotes = false;
    }
  }
  return out;
}

}  // namespace granule::examples
