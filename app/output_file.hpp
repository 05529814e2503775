#pragma once
// Where a command writes a file (--csv, --out, --output): "-" is standard
// output; an existing path that is not a regular file (a terminal, a FIFO,
// /dev/stdout) is written in place, never renamed over; anything else is
// written beside the target and renamed over it at commit(), so a reader
// never sees half a file and a failed write leaves the old one.
#include <cstdio>
#include <string>

namespace nlsoft::console {

class OutputFile {
 public:
  explicit OutputFile(const std::string& path);  // throws CliError, naming the path
  ~OutputFile();                                 // without commit(): the temporary is removed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::FILE* get() const { return f_; }
  // Flushes and checks every write, then moves the file into place.
  // Throws CliError; the target is then untouched.
  void commit();

 private:
  std::string path_, tmp_;  // tmp_ empty: written in place
  std::FILE* f_ = nullptr;
  bool stdout_ = false;
};

}  // namespace nlsoft::console
