#include "app/model/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "host/files/cli_error.hpp"
#include "app/model/error.hpp"
#include "app/model/model_section.hpp"
#include "host/files/output_file.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::model {

namespace {

// std::ostream onto the FILE* of an OutputFile.
class FileBuf : public std::streambuf {
 public:
  explicit FileBuf(std::FILE* f) : f_(f) {}

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    return std::fputc(c, f_) == EOF ? traits_type::eof() : c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    return std::streamsize(std::fwrite(s, 1, size_t(n), f_));
  }

 private:
  std::FILE* f_;
};

}  // namespace

void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& fill) {
  try {
    host::OutputFile file(path);
    FileBuf buf(file.get());
    std::ostream out(&buf);
    fill(out);
    out.flush();
    if (!out) throw PipelineError("write to '" + path + "' failed (disk full?)");
    file.commit();
  } catch (const host::CliError& e) {
    throw PipelineError(e.what());
  }
}

void write_file_atomic(const std::string& path, const std::vector<uint8_t>& bytes) {
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

std::string read_text_file(const std::string& path, const host::InputKind& kind) {
  // A missing file in the pipeline's own words, as its other errors.
  if (::access(path.c_str(), F_OK) != 0) throw PipelineError("cannot open '" + path + "': " + std::strerror(errno));
  try {
    return host::read_input_file(path, kind);
  } catch (const host::CliError& e) {
    throw PipelineError(e.what());
  }
}

std::vector<uint8_t> read_model_bytes(const std::string& path) {
  const std::string text = read_text_file(path, {"model file", model_file_with_sections_max(), false});
  return std::vector<uint8_t>(text.begin(), text.end());
}

}  // namespace nlsoft::model
