#pragma once
// Whole-file reads and atomic writes for the io headers. Every failure is an IoError that names
// the operation, the path and the operating system's reason (its strerror text), including a
// directory given where a file is expected (an std::ifstream would open it and throw
// std::ios_base::failure on the first read).
//
// write_file_atomically writes "<path>.tmp" and renames it over `path`; whatever fails on the
// way, the temporary file is removed. With `durable` the data reach the disk before the rename
// (fsync of the file) and the rename itself is made durable (fsync of the directory), so that
// after a power loss `path` holds either the old or the new content (POSIX; elsewhere the
// rename alone).
#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>

#include "granule/core/error.hpp"

#if defined(_WIN32)
#include <cstdio>
#else
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

namespace granule::io {

namespace detail {

/// The operating system's text for error number `err` (strerror, thread-safe).
inline std::string os_reason(int err) { return std::generic_category().message(err); }

#if !defined(_WIN32)
// Closes a descriptor on every way out.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
  int release() {
    const int f = fd;
    fd = -1;
    return f;
  }
};
#endif

}  // namespace detail

/// The bytes of the file at `path`. `where` prefixes the messages (e.g. "read_checkpoint").
inline std::string read_file(const std::filesystem::path& path, const std::string& where) {
  const std::string name = "'" + path.string() + "'";
#if defined(_WIN32)
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(where + ": cannot read " + name + ": it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(where + ": cannot open " + name + ": " + detail::os_reason(errno));
  try {
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  } catch (const std::exception& e) {
    throw IoError(where + ": reading " + name + " failed: " + e.what());
  }
#else
  detail::FileDescriptor f;
  do {
    f.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  } while (f.fd < 0 && errno == EINTR);
  if (f.fd < 0) throw IoError(where + ": cannot open " + name + ": " + detail::os_reason(errno));
  struct stat st {};
  if (::fstat(f.fd, &st) != 0) throw IoError(where + ": cannot stat " + name + ": " + detail::os_reason(errno));
  if (S_ISDIR(st.st_mode)) throw IoError(where + ": cannot read " + name + ": " + detail::os_reason(EISDIR));
  std::string out;
  if (S_ISREG(st.st_mode) && st.st_size > 0) out.reserve(static_cast<std::size_t>(st.st_size));
  char buf[1 << 16];
  for (;;) {
    const ssize_t got = ::read(f.fd, buf, sizeof(buf));
    if (got < 0) {
      if (errno == EINTR) continue;
      throw IoError(where + ": reading " + name + " failed: " + detail::os_reason(errno));
    }
    if (got == 0) break;
    out.append(buf, static_cast<std::size_t>(got));
  }
  return out;
#endif
}

/// Writes `size` bytes at `data` to `path` through "<path>.tmp" and a rename (see above).
inline void write_file_atomically(const std::filesystem::path& path, const void* data, std::size_t size,
                                  const std::string& where, bool durable) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  const std::string tmp_name = "'" + tmp.string() + "'";
#if defined(_WIN32)
  (void)durable;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(where + ": cannot open " + tmp_name + " for writing: " + detail::os_reason(errno));
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.flush();
    if (!out) {
      const int err = errno;
      out.close();
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw IoError(where + ": writing " + tmp_name + " failed: " + detail::os_reason(err));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError(where + ": cannot rename " + tmp_name + " to '" + path.string() + "': " + ec.message());
  }
#else
  const auto fail = [&](const std::string& what, int err) {
    ::unlink(tmp.c_str());
    throw IoError(where + ": " + what + ": " + detail::os_reason(err));
  };
  detail::FileDescriptor f;
  do {
    f.fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  } while (f.fd < 0 && errno == EINTR);
  // (Nothing to remove: the temporary file was not created, or is not ours to remove.)
  if (f.fd < 0) throw IoError(where + ": cannot open " + tmp_name + " for writing: " + detail::os_reason(errno));
  const char* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    const ssize_t put = ::write(f.fd, p, left);
    if (put < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(f.release());
      fail("writing " + tmp_name + " failed", err);
    }
    p += put;
    left -= static_cast<std::size_t>(put);
  }
  if (durable && ::fsync(f.fd) != 0) {
    const int err = errno;
    ::close(f.release());
    fail("flushing " + tmp_name + " to disk failed", err);
  }
  // close() may report a deferred write error (network file systems).
  if (::close(f.release()) != 0) fail("closing " + tmp_name + " failed", errno);
  if (::rename(tmp.c_str(), path.c_str()) != 0)
    fail("cannot rename " + tmp_name + " to '" + path.string() + "'", errno);
  if (durable) {
    std::filesystem::path dir = path.parent_path();
    if (dir.empty()) dir = ".";
    detail::FileDescriptor d;
    d.fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (d.fd < 0 || ::fsync(d.fd) != 0)
      throw IoError(where + ": '" + path.string() + "' was written, but flushing its directory '" + dir.string() +
                    "' to disk failed: " + detail::os_reason(errno));
  }
#endif
}

}  // namespace granule::io
