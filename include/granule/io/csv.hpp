#pragma once
// CSV time-series writer. The header names each column with its unit in brackets,
// e.g. "time [s],force_z [N]"; every row holds one number per column, written in the
// shortest decimal form that reads back to exactly the same double (std::to_chars, so no
// digit is lost; at most max_digits10 = 17 significant digits). Non-finite values are
// written as nan, inf, -inf. Each row is written with a single call and, by default,
// flushed, so the file is valid after every row; a run that restarts can append to it
// (the header is checked, and an incomplete last line left by a crash is dropped).
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "granule/core/error.hpp"
#include "granule/io/file.hpp"

namespace granule::io {

/// One column: name and unit ("" for dimensionless counts, written without brackets).
struct CsvColumn {
  std::string name;
  std::string unit;
};

struct CsvOptions {
  bool flush_every_row = true;  ///< flush after each row (the file is valid after each row)
  bool append = false;          ///< continue an existing file with the same header
};

/// Appends rows of doubles to a CSV file.
class CsvWriter {
 public:
  CsvWriter(std::filesystem::path path, std::vector<CsvColumn> columns, CsvOptions options = {})
      : path_(std::move(path)), columns_(std::move(columns)), options_(options) {
    require(!columns_.empty(), "io::CsvWriter", "number of columns", 0.0, "[1, inf)");
    for (const CsvColumn& c : columns_) {
      for (const std::string* s : {&c.name, &c.unit}) {
        if (s->find_first_of(",\"\n\r[]") != std::string::npos) {
          throw InvalidParameter("io::CsvWriter: column '" + c.name + "' [" + c.unit +
                                 "]: names and units must not contain , \" [ ] or line breaks");
        }
      }
      require(!c.name.empty(), "io::CsvWriter", "column name length", 0.0, "[1, inf)");
    }
    header_.clear();
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      if (k > 0) header_ += ',';
      header_ += columns_[k].name;
      if (!columns_[k].unit.empty()) header_ += " [" + columns_[k].unit + "]";
    }
    const bool continuing = options_.append && std::filesystem::exists(path_) && std::filesystem::file_size(path_) > 0;
    if (continuing) prepare_append();
    file_.open(path_, continuing ? std::ios::binary | std::ios::app : std::ios::binary | std::ios::trunc);
    if (!file_)
      throw IoError("io::CsvWriter: cannot open '" + path_.string() + "' for writing: " + detail::os_reason(errno));
    if (!continuing) {
      file_ << header_ << '\n';
      file_.flush();
      if (!file_) throw IoError("io::CsvWriter: writing '" + path_.string() + "' failed");
    }
  }

  /// Writes one row; `values.size()` must equal the number of columns.
  void write_row(std::span<const double> values) {
    require(values.size() == columns_.size(), "io::CsvWriter::write_row", "number of values",
            static_cast<double>(values.size()), std::to_string(columns_.size()) + " (the number of columns)");
    line_.clear();
    char buf[32];
    for (std::size_t k = 0; k < values.size(); ++k) {
      if (k > 0) line_ += ',';
      const auto res = std::to_chars(buf, buf + sizeof(buf), values[k]);
      line_.append(buf, res.ptr);
    }
    line_ += '\n';
    file_.write(line_.data(), static_cast<std::streamsize>(line_.size()));
    if (options_.flush_every_row) file_.flush();
    if (!file_) throw IoError("io::CsvWriter: writing '" + path_.string() + "' failed");
    ++rows_;
  }
  void write_row(std::initializer_list<double> values) { write_row(std::span<const double>(values.begin(), values.size())); }

  void flush() { file_.flush(); }

  const std::string& header() const { return header_; }
  std::size_t column_count() const { return columns_.size(); }
  /// Rows written by this writer (not counting rows already in an appended file).
  std::size_t rows() const { return rows_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  void prepare_append() {
    const std::string text = read_file(path_, "io::CsvWriter (appending)");
    const auto eol = text.find('\n');
    const std::string first = text.substr(0, eol == std::string::npos ? text.size() : eol);
    if (first != header_) {
      throw IoError("io::CsvWriter: cannot append to '" + path_.string() + "': its header '" + first +
                    "' differs from '" + header_ + "'");
    }
    const auto last_eol = text.rfind('\n');
    if (last_eol + 1 != text.size()) std::filesystem::resize_file(path_, last_eol + 1);  // partial row
  }

  std::filesystem::path path_;
  std::vector<CsvColumn> columns_;
  CsvOptions options_;
  std::string header_;
  std::string line_;
  std::ofstream file_;
  std::size_t rows_ = 0;
};

}  // namespace granule::io
