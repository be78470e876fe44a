#include "gfmd/core/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "gfmd/core/error.hpp"

namespace gfmd {

std::string errno_message(int err) { return std::error_code(err, std::generic_category()).message(); }

void AtomicFile::fail(const std::string& why) const { throw std::runtime_error(path_ + ": " + why); }

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp." + std::to_string(static_cast<long>(::getpid()))) {}

AtomicFile::~AtomicFile() {
  if (!committed_) ::unlink(tmp_.c_str());
}

// Writes the buffer to the temporary: truncated first, or appended to; synced or not.
void AtomicFile::put(const void* data, std::size_t size, bool append, bool sync) {
  const int fd = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (append ? O_APPEND : O_TRUNC), 0666);
  if (fd < 0) fail("cannot create temporary file '" + tmp_ + "': " + errno_message(errno));
  const auto* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      fail("cannot write temporary file '" + tmp_ + "': " + errno_message(err));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (sync && ::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    fail("cannot fsync temporary file '" + tmp_ + "': " + errno_message(err));
  }
  if (::close(fd) != 0) fail("cannot close temporary file '" + tmp_ + "': " + errno_message(errno));
}

void AtomicFile::write_bytes(const void* data, std::size_t size) { put(data, size, false, true); }

void AtomicFile::append_bytes(const void* data, std::size_t size) {
  put(data, size, started_, false);
  started_ = true;
}

// fsyncs a temporary written by someone else (e.g. the NetCDF library).
void AtomicFile::sync_tmp() const {
  const int fd = ::open(tmp_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail("cannot reopen temporary file '" + tmp_ + "': " + errno_message(errno));
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    fail("cannot fsync temporary file '" + tmp_ + "': " + errno_message(err));
  }
  ::close(fd);
}

// Renames the (synced) temporary over the path and syncs the directory (best effort).
void AtomicFile::commit() {
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    fail("cannot rename '" + tmp_ + "' to the output file: " + errno_message(errno));
  committed_ = true;
  const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
  const std::filesystem::path dir = parent.empty() ? std::filesystem::path(".") : parent;
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_bytes_atomic(const std::string& path, const void* data, std::size_t size) {
  AtomicFile target(path);
  target.write_bytes(data, size);
  target.commit();
}

void write_text_atomic(const std::string& path, const std::string& content) {
  write_bytes_atomic(path, content.data(), content.size());
}

namespace {
// Throws unless st describes a regular file: a directory, device, FIFO or socket is named.
void require_regular_mode(const std::string& path, const struct stat& st, const std::string& what) {
  if (S_ISDIR(st.st_mode)) throw InputError(path, "is a directory, not a " + what);
  if (!S_ISREG(st.st_mode))
    throw InputError(path, "not a regular file (a device, FIFO or socket); the " + what + " must be a file");
}
}  // namespace

void require_regular_file(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(path, "cannot open the " + what + ": " + errno_message(errno));
  require_regular_mode(path, st, what);
}

std::string read_regular_file(const std::string& path, std::size_t max_bytes, const std::string& what) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; fstat then refuses it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw InputError(path, "cannot open the " + what + ": " + errno_message(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    ::close(fd);
    throw InputError(path, "cannot open the " + what + ": " + errno_message(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    require_regular_mode(path, st, what);
  }
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    throw InputError(path, "the " + what + " is " + std::to_string(st.st_size) + " bytes, more than the " +
                               std::to_string(max_bytes) + " bytes allowed");
  }
  std::string out(static_cast<std::size_t>(st.st_size), '\0');
  std::size_t got = 0;
  while (got < out.size()) {
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      throw InputError(path, "cannot read the " + what + ": " + errno_message(err));
    }
    if (n == 0) break;  // shrank while reading
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  out.resize(got);
  return out;
}

}  // namespace gfmd
