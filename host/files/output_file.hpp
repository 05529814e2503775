#pragma once
// Where a command writes a file (--csv, --out, --output, --svg):
//  - "-" is standard output;
//  - a name for one of this process's descriptors (/dev/stdout, /dev/fd/N,
//    /proc/self/fd/N, also through links) is written through that
//    descriptor, where it stands: `> f.csv` gets the bytes, `>>` appends;
//  - a character device, FIFO or socket is written in place;
//  - a symlink is followed to its real path first, so the link stays a link
//    and its target gets the new content;
//  - a regular file (or a new one) is written beside the real path and
//    renamed over it at commit(), so a reader never sees half a file and a
//    failed write leaves the old one.
// Nothing but the named file (or the link's target) is ever replaced.
#include <cstdio>
#include <string>

namespace nlsoft::host {

// How a path given for output is to be written (exposed for tests).
struct OutputTarget {
  enum Kind { Stdout, Descriptor, InPlace, Replace } kind = Replace;
  std::string path;  // InPlace/Replace: the real path (links resolved)
  int fd = -1;       // Descriptor: this process's descriptor
};
// Throws CliError naming `path` (a directory, a loop of links, ...).
OutputTarget output_target(const std::string& path);

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
  std::string path_, real_, tmp_;  // tmp_ empty: written in place
  std::FILE* f_ = nullptr;
  bool stdout_ = false;
};

}  // namespace nlsoft::host
