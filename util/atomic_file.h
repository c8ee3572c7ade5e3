#ifndef SOFTBENCH_UTIL_ATOMIC_FILE_H_
#define SOFTBENCH_UTIL_ATOMIC_FILE_H_

#include <string>
#include <string_view>

namespace softbench {

// Writes a file so that readers see either the old file or the complete new
// one: the bytes go to a temporary file in the same directory, are flushed to
// disk, and the temporary is renamed over the target by Commit(). Destroyed
// without Commit() (an error, an exception), it removes the temporary.
// Failures throw InputError naming the path.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(std::string path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

  void Append(std::string_view bytes);
  void Commit();

 private:
  [[noreturn]] void Fail(const char* what);

  std::string path_;
  std::string temporary_;
  int fd_ = -1;
};

// The whole of `contents` through an AtomicFileWriter.
void WriteFileAtomically(const std::string& path, std::string_view contents);

// A report directory written atomically: files go into a fresh staging
// directory beside `path`, and Commit() swaps it in for the old directory
// (which is then removed). Destroyed without Commit(), it removes the staging
// directory and leaves the previous report untouched.
class AtomicDirectory {
 public:
  explicit AtomicDirectory(std::string path);
  ~AtomicDirectory();
  AtomicDirectory(const AtomicDirectory&) = delete;
  AtomicDirectory& operator=(const AtomicDirectory&) = delete;

  // Path of `name` inside the staging directory.
  std::string File(std::string_view name) const;
  void Commit();

 private:
  std::string path_;
  std::string staging_;
  bool committed_ = false;
};

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_ATOMIC_FILE_H_
