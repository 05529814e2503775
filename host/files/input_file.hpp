#pragma once
// Reading a file the user named (a model, a parameter file, a reference or
// dataset CSV, a script): what cannot be such a file is refused before a
// byte is read, in words: a directory, a device (/dev/zero would otherwise
// be read until memory runs out), anything larger than the kind of file can
// be. A FIFO (`--script <(generate)`) is read, up to the same bound.
#include <cstdint>
#include <string>

namespace nlsoft::host {

struct InputKind {
  const char* what;       // "model file", "script", ...: for the messages
  uint64_t max_bytes;     // larger is refused
  bool stream_ok = true;  // false: a regular file only (a FIFO is refused too)
  // How the bound reads in a refusal ("this firmware takes models of at
  // most"); null: "a <what> is at most".
  const char* limit_words = nullptr;
};

// The console's own text inputs. Real ones are a few KiB; the bounds only
// keep a wrong name (a device, a log, a dataset) from being read whole.
inline constexpr InputKind kScriptFile{"script", 4u << 20};
inline constexpr InputKind kParamsFile{"parameter file", 1u << 20};
inline constexpr InputKind kReferenceCsv{"reference table CSV", 4u << 20};
inline constexpr InputKind kRigFile{"rig file", 1u << 20, false};

// Throws CliError (exit 2) naming the path and what is wrong with it.
std::string read_input_file(const std::string& path, const InputKind& kind);

// The same checks without reading, for readers that stream the file
// themselves (a library opening it by name). A FIFO is refused here.
void check_input_file(const std::string& path, const InputKind& kind);

// "12.5 MiB", "480 bytes": a size in messages.
std::string byte_size(uint64_t bytes);

}  // namespace nlsoft::host
