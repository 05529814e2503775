#pragma once
// What a model file carries after its model: sections the firmware never
// reads. The model is the file's first model_file_size(L, P) bytes (header,
// layers, parameters and the CRC-32 that is the model's hash,
// shared/model_file.hpp); `train` appends its fit (app/model/model_fit.hpp)
// as a section:
//
//   off  size  field
//   0    4     magic "NLSX"
//   4    1     kind (1: the fit, JSON text)
//   5    3     reserved, zero
//   8    4     length T of the text
//   12   T     the text
//   12+T 4     CRC-32 of the section's bytes before it
//
// The console uploads, embeds in images and hashes the model part only, so
// a firmware gets the same bytes, and reports the same hash, with or without
// sections. Readers bound a file by the largest model the console holds
// and room for its sections (model_file_with_sections_max): a fit with its
// ARX baseline's coefficients, (p + 1) x n numbers, is about 13 KB at the
// console's largest dimensions (p = 88, n = 6), a few KB for the shipped
// rigs. Header-only: the upload, `simulate` and the image build use it
// without the model pipeline's library.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "shared/capacity.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::model {

constexpr uint8_t kSectionFit = 1;
constexpr size_t kSectionOverhead = 16;
// What the sections after a model may take in all; train refuses to write more.
constexpr size_t kSectionsMax = 64 * 1024;

constexpr size_t model_file_with_sections_max() { return model_file_max<HostCapacity>() + kSectionsMax; }

struct ModelFileParts {
  size_t model_size = 0;     // the model: bytes [0, model_size)
  std::string fit;           // the fit section's text; empty: none
  bool bad_trailer = false;  // bytes after the model that are no section
  std::string fault;         // with bad_trailer: what is wrong there, in words, with the byte offset
};

// Never fails: a file too short for its header, or with another magic, is
// all model (parse_model then says what is wrong with it).
inline ModelFileParts split_model_file(const uint8_t* buf, size_t len) {
  ModelFileParts out;
  out.model_size = len;
  if (len < kModelHeaderSize || std::memcmp(buf, "NLSM", 4) != 0) return out;
  const size_t model = model_file_size(buf[model_offset::kLayers], detail::rd32(buf + model_offset::kParams));
  if (len <= model) return out;
  out.model_size = model;
  size_t at = model;
  while (at < len) {
    auto bad = [&](std::string fault) {
      out.bad_trailer = true;
      out.fault = "after the model (" + std::to_string(model) + " bytes), " + fault;
      return out;
    };
    if (len - at >= 4 && std::memcmp(buf + at, "NLSX", 4) != 0)
      return bad("the bytes at offset " + std::to_string(at) + " are no section (no \"NLSX\")");
    if (len - at < kSectionOverhead)
      return bad("the file ends inside the section at offset " + std::to_string(at) + " (truncated: " +
                 std::to_string(len - at) + " of its at least " + std::to_string(kSectionOverhead) + " bytes)");
    const size_t text = detail::rd32(buf + at + 8);
    if (text > len - at - kSectionOverhead)
      return bad("the file ends inside the section at offset " + std::to_string(at) + " (truncated: it holds " +
                 std::to_string(text) + " bytes of text, the file " + std::to_string(len - at - kSectionOverhead) +
                 ")");
    const size_t body = 12 + text;
    if (crc32(buf + at, body) != detail::rd32(buf + at + body))
      return bad("the section at offset " + std::to_string(at) + " fails its CRC-32 (damaged)");
    // Kinds this console does not know are skipped: a later console may add some.
    if (buf[at + 4] == kSectionFit) out.fit.assign(reinterpret_cast<const char*>(buf + at + 12), text);
    at += body + 4;
  }
  return out;
}

inline ModelFileParts split_model_file(const std::vector<uint8_t>& bytes) {
  return split_model_file(bytes.data(), bytes.size());
}

inline std::vector<uint8_t> model_section(uint8_t kind, const std::string& text) {
  std::vector<uint8_t> s(kSectionOverhead + text.size(), 0);
  std::memcpy(s.data(), "NLSX", 4);
  s[4] = kind;
  detail::wr32(s.data() + 8, uint32_t(text.size()));
  std::memcpy(s.data() + 12, text.data(), text.size());
  detail::wr32(s.data() + 12 + text.size(), crc32(s.data(), 12 + text.size()));
  return s;
}

}  // namespace nlsoft::model
