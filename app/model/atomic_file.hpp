#pragma once
// Writes that either fully happen or leave the destination untouched: a
// crash, a full disk or a bad value discovered half way never leaves a
// truncated model or CSV where the old good one was.
#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace nlsoft::pipeline {

// Streams into a temporary beside path, flushes, then renames over it
// (app/output_file.hpp: "-" is standard output, a device is written in
// place). If `fill` throws or the write fails, path keeps its old content.
// Throws PipelineError.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& fill);

void write_file_atomic(const std::string& path, const std::vector<uint8_t>& bytes);

// Whole file as bytes; throws PipelineError naming the path.
std::vector<uint8_t> read_file_bytes(const std::string& path);

}  // namespace nlsoft::pipeline
