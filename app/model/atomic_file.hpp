#pragma once
// Writes that either fully happen or leave the destination untouched: a
// crash, a full disk or a bad value discovered half way never leaves a
// truncated model or CSV where the old good one was.
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "host/files/input_file.hpp"

namespace nlsoft::model {

// Streams into a temporary beside path, flushes, then renames over it
// (host/files/output_file.hpp: "-" is standard output, a device is written in
// place). If `fill` throws or the write fails, path keeps its old content.
// Throws PipelineError.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& fill);

void write_file_atomic(const std::string& path, const std::vector<uint8_t>& bytes);

// A file the user named, whole (host/files/input_file.hpp: bounded, a regular
// file or a FIFO); throws PipelineError naming the path.
std::string read_text_file(const std::string& path, const host::InputKind& kind);
// A model file: a regular file no larger than the format allows.
std::vector<uint8_t> read_model_bytes(const std::string& path);

}  // namespace nlsoft::model
