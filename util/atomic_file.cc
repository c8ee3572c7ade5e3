#include "util/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "util/input_error.h"

namespace softbench {

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  if (path == "-") {
    std::cout << contents << std::flush;
    return;
  }
  const std::filesystem::path target(path);
  const std::filesystem::path directory =
      target.has_parent_path() ? target.parent_path() : ".";
  std::string temporary =
      (directory / ("." + target.filename().string() + ".XXXXXX")).string();
  const int fd = mkstemp(temporary.data());
  if (fd < 0) {
    throw InputError(path + ": cannot create a file in '" + directory.string() +
                     "' (" + std::strerror(errno) +
                     "); choose a writable output directory");
  }
  const auto fail = [&](const char* what) {
    const std::string reason = std::strerror(errno);
    close(fd);
    std::remove(temporary.c_str());
    throw InputError(path + ": " + what + " failed (" + reason + ")");
  };
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n =
        write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail("write");
    }
    written += static_cast<size_t>(n);
  }
  // mkstemp creates 0600; give the result the usual permissions.
  if (fchmod(fd, 0644) != 0) fail("chmod");
  if (fsync(fd) != 0) fail("fsync");
  if (close(fd) != 0) {
    std::remove(temporary.c_str());
    throw InputError(path + ": close failed (" + std::strerror(errno) + ")");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw InputError(path + ": cannot replace the file (" + reason + ")");
  }
}

}  // namespace softbench
