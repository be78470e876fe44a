// Files as the rest of the library needs them (core): atomic writes through a temporary
// that is fsync'ed and renamed into place, and bounded reads of regular files only.
#pragma once

#include <cstddef>
#include <string>

namespace gfmd {

// strerror-like text of an errno value.
std::string errno_message(int err);

// A file written atomically: the data go to "<path>.tmp.<pid>" in the same directory, which
// commit() fsyncs and renames over <path>; the temporary is removed on destruction unless it
// was committed. Failures throw std::runtime_error("<path>: <reason>") (fail()).
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  [[nodiscard]] const std::string& tmp() const { return tmp_; }
  [[noreturn]] void fail(const std::string& why) const;
  // Writes the whole buffer to the temporary and fsyncs it.
  void write_bytes(const void* data, std::size_t size);
  // Appends to the temporary (the first call starts it empty), without syncing: a file
  // written in pieces, then sync_tmp() and commit().
  void append_bytes(const void* data, std::size_t size);
  // fsyncs a temporary written by someone else (e.g. the NetCDF library).
  void sync_tmp() const;
  // Renames the (synced) temporary over the path and syncs the directory (best effort).
  void commit();

 private:
  void put(const void* data, std::size_t size, bool append, bool sync);
  std::string path_, tmp_;
  bool committed_ = false, started_ = false;
};

// Writes size bytes to path atomically (tmp + fsync + rename + fsync of the directory).
// Throws std::runtime_error("<path>: <reason>") on failure.
void write_bytes_atomic(const std::string& path, const void* data, std::size_t size);
void write_text_atomic(const std::string& path, const std::string& content);

// Reads a whole input file. Only regular files are read (a device, FIFO, socket or
// directory is refused without blocking) and only up to max_bytes (checked before reading).
// Throws InputError(path, "<what>: <reason>").
std::string read_regular_file(const std::string& path, std::size_t max_bytes, const std::string& what);

// Throws InputError(path, ...) unless path names an existing regular file (links followed).
void require_regular_file(const std::string& path, const std::string& what);

}  // namespace gfmd
