#include "util/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "util/input_error.h"

namespace softbench {
namespace fs = std::filesystem;

AtomicFileWriter::AtomicFileWriter(std::string path) : path_(std::move(path)) {
  const fs::path target(path_);
  const fs::path directory =
      target.has_parent_path() ? target.parent_path() : ".";
  temporary_ =
      (directory / ("." + target.filename().string() + ".XXXXXX")).string();
  fd_ = mkstemp(temporary_.data());
  if (fd_ < 0) {
    throw InputError(path_ + ": cannot create a file in '" +
                     directory.string() + "' (" + std::strerror(errno) +
                     "); choose a writable output directory");
  }
}

AtomicFileWriter::~AtomicFileWriter() {
  if (fd_ >= 0) {
    close(fd_);
    std::remove(temporary_.c_str());
  }
}

void AtomicFileWriter::Fail(const char* what) {
  const std::string reason = std::strerror(errno);
  close(fd_);
  fd_ = -1;
  std::remove(temporary_.c_str());
  throw InputError(path_ + ": " + what + " failed (" + reason + ")");
}

void AtomicFileWriter::Append(std::string_view bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n =
        write(fd_, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      Fail("write");
    }
    written += static_cast<size_t>(n);
  }
}

void AtomicFileWriter::Commit() {
  // mkstemp creates 0600; give the result the usual permissions.
  if (fchmod(fd_, 0644) != 0) Fail("chmod");
  if (fsync(fd_) != 0) Fail("fsync");
  const int fd = fd_;
  fd_ = -1;
  if (close(fd) != 0) {
    std::remove(temporary_.c_str());
    throw InputError(path_ + ": close failed (" + std::strerror(errno) + ")");
  }
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary_.c_str());
    throw InputError(path_ + ": cannot replace the file (" + reason + ")");
  }
}

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  AtomicFileWriter writer(path);
  writer.Append(contents);
  writer.Commit();
}

AtomicDirectory::AtomicDirectory(std::string path) : path_(std::move(path)) {
  fs::path target(path_);
  if (!target.has_filename()) target = target.parent_path();
  const fs::path parent = target.has_parent_path() ? target.parent_path() : ".";
  std::string staging =
      (parent / ("." + target.filename().string() + ".XXXXXX")).string();
  if (mkdtemp(staging.data()) == nullptr) {
    throw InputError(path_ + ": cannot create a directory in '" +
                     parent.string() + "' (" + std::strerror(errno) +
                     "); choose a writable report directory");
  }
  staging_ = staging;
  path_ = target.string();
}

AtomicDirectory::~AtomicDirectory() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

std::string AtomicDirectory::File(std::string_view name) const {
  return (fs::path(staging_) / name).string();
}

void AtomicDirectory::Commit() {
  std::error_code error;
  chmod(staging_.c_str(), 0755);
  // Move the old report aside first: rename cannot replace a non-empty
  // directory, and readers must never see a half-removed one.
  std::string old;
  const fs::file_status status = fs::symlink_status(path_, error);
  if (error && error != std::errc::no_such_file_or_directory) {
    throw InputError(path_ + ": cannot write the report there (" +
                     error.message() + "); choose another directory");
  }
  if (fs::exists(status)) {
    if (!fs::is_directory(status)) {
      throw InputError(path_ +
                       ": exists and is not a directory; choose "
                       "another report directory");
    }
    old = staging_ + ".old";
    fs::rename(path_, old, error);
    if (error) {
      throw InputError(path_ + ": cannot replace the report (" +
                       error.message() + ")");
    }
  }
  fs::rename(staging_, path_, error);
  if (error) {
    if (!old.empty()) fs::rename(old, path_, error);
    throw InputError(path_ + ": cannot write the report (" + error.message() +
                     ")");
  }
  committed_ = true;
  if (!old.empty()) fs::remove_all(old, error);
}

}  // namespace softbench
