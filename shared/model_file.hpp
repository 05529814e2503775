#pragma once
// The model file: one binary format for the console, firmware upload and the
// model an image embeds. Little-endian; the byte layout below is the whole specification.
//
//   off  size  field
//   0    4     magic "NLSM"
//   4    1     format version (1)
//   5    1     flags: bit 0 residual output
//   6    1     m      7  1  n      8  1  w      9  1  nd     10 1  dd
//   11   1     layer count L
//   12   4     parameter count P (float32 values)
//   16   1     platform id (0 msd, 1 hasel, 2 tendon, 255 none)
//   17   7     reserved, zero
//   24   8 L   layers: kind u8, act u8, rec_act u8, reset_after u8, in u16, out u16
//   ..   4 P   parameters (model.hpp: normalisation, then weights)
//   ..   4     CRC-32 of every byte before it; also the model hash
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "shared/crc32.hpp"
#include "shared/model.hpp"

namespace nlsoft {

constexpr uint8_t kModelFormatVersion = 1;
constexpr size_t kModelHeaderSize = 24;
constexpr size_t kModelLayerSize = 8;

// Header fields by name, for code that reads a file's shape before
// parsing it (the firmware refusing a model for another plant).
namespace model_offset {
constexpr size_t kMagic = 0, kVersion = 4, kFlags = 5, kM = 6, kN = 7, kW = 8, kNd = 9, kDd = 10, kLayers = 11,
                 kParams = 12, kPlatform = 16, kLayerTable = 24;
}  // namespace model_offset

constexpr size_t model_file_size(int layers, uint32_t params) {
  return kModelHeaderSize + kModelLayerSize * size_t(layers) + 4 * size_t(params) + 4;
}

// The most parameters a model within capacity Cap can hold (normalisation,
// then weights; model.hpp), and the size of its file: what a transfer
// buffer must take.
template <class Cap>
constexpr uint32_t model_params_max() {
  return uint32_t(Cap::weights) + 2u * uint32_t(Dims<Cap>::p) + 2u * uint32_t(Cap::n);
}
template <class Cap>
constexpr size_t model_file_max() {
  return model_file_size(Cap::layers, model_params_max<Cap>());
}

namespace detail {
inline uint16_t rd16(const uint8_t* p) { return uint16_t(p[0] | (p[1] << 8)); }
inline uint32_t rd32(const uint8_t* p) {
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}
inline void wr16(uint8_t* p, uint16_t v) {
  p[0] = uint8_t(v);
  p[1] = uint8_t(v >> 8);
}
inline void wr32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i));
}
}  // namespace detail

// Parses and validates a model file. The parameters are copied into the
// caller's storage (capacity in floats), or, with storage == nullptr, used
// where they are in buf (which must then outlive M, be 4-byte aligned and
// the machine little-endian: an MCU runs its built-in model from flash and an
// uploaded one from the transfer buffer, with no second copy in RAM). On any
// error M is left untouched.
template <class Cap>
Status parse_model(const uint8_t* buf, size_t len, Model<Cap>& M, float* storage, uint32_t storage_cap,
                   uint8_t* platform = nullptr) {
  using namespace detail;
  if (buf == nullptr || len < kModelHeaderSize + 4) return Status::BadFormat;
  if (std::memcmp(buf, "NLSM", 4) != 0 || buf[model_offset::kVersion] != kModelFormatVersion) return Status::BadFormat;
  const int L = buf[model_offset::kLayers];
  const uint32_t P = rd32(buf + model_offset::kParams);
  if (L > Cap::layers) return Status::TooLarge;
  if (storage ? P > storage_cap : P > model_params_max<Cap>()) return Status::TooLarge;
  if (len != model_file_size(L, P)) return Status::WrongSize;
  const uint32_t crc = rd32(buf + len - 4);
  if (crc32(buf, len - 4) != crc) return Status::BadChecksum;

  Model<Cap> c;
  c.residual = (buf[model_offset::kFlags] & 1u) != 0;
  c.m = buf[model_offset::kM];
  c.n = buf[model_offset::kN];
  c.w = buf[model_offset::kW];
  c.nd = buf[model_offset::kNd];
  c.dd = buf[model_offset::kDd];
  c.layer_count = uint8_t(L);
  const uint8_t* lp = buf + kModelHeaderSize;
  for (int i = 0; i < L; ++i, lp += kModelLayerSize) {
    Layer& l = c.layer[i];
    l.kind = LayerKind(lp[0]);
    l.act = Activation(lp[1]);
    l.rec_act = Activation(lp[2]);
    l.reset_after = lp[3] != 0;
    l.in = rd16(lp + 4);
    l.out = rd16(lp + 6);
  }
  // Everything is checked against the file's own bytes before the storage
  // is written, so a bad file never clobbers a model still in use.
  c.param_count = P;
  const Status shape = check_model_shape(c);
  if (shape != Status::Ok) return shape;
  const uint8_t* pp = lp;
  for (uint32_t i = 0; i < P; ++i) {
    const uint32_t bits = rd32(pp + 4 * i);
    float v;
    std::memcpy(&v, &bits, 4);
    if (!(v - v == 0.0f)) return Status::NotFinite;
  }
  if (storage) {
    for (uint32_t i = 0; i < P; ++i) {
      const uint32_t bits = rd32(pp + 4 * i);
      std::memcpy(&storage[i], &bits, 4);
    }
    c.params = storage;
  } else {
    const uint32_t one = 1;
    uint8_t first;
    std::memcpy(&first, &one, 1);
    if (first != 1 || reinterpret_cast<uintptr_t>(pp) % alignof(float) != 0) return Status::BadFormat;
    c.params = reinterpret_cast<const float*>(pp);
  }
  c.hash = crc;
  M = c;
  if (platform) *platform = buf[model_offset::kPlatform];
  return Status::Ok;
}

// Writes M as a model file into out (capacity cap). Returns the size, or 0
// if it does not fit.
template <class Cap>
size_t write_model(const Model<Cap>& M, uint8_t platform, uint8_t* out, size_t cap) {
  using namespace detail;
  const size_t size = model_file_size(M.layer_count, M.param_count);
  if (out == nullptr || size > cap) return 0;
  std::memset(out, 0, kModelHeaderSize);
  std::memcpy(out, "NLSM", 4);
  namespace at = model_offset;
  out[at::kVersion] = kModelFormatVersion;
  out[at::kFlags] = M.residual ? 1 : 0;
  out[at::kM] = M.m;
  out[at::kN] = M.n;
  out[at::kW] = M.w;
  out[at::kNd] = M.nd;
  out[at::kDd] = M.dd;
  out[at::kLayers] = M.layer_count;
  wr32(out + at::kParams, M.param_count);
  out[at::kPlatform] = platform;
  uint8_t* lp = out + kModelHeaderSize;
  for (int i = 0; i < M.layer_count; ++i, lp += kModelLayerSize) {
    const Layer& l = M.layer[i];
    lp[0] = uint8_t(l.kind);
    lp[1] = uint8_t(l.act);
    lp[2] = uint8_t(l.rec_act);
    lp[3] = l.reset_after ? 1 : 0;
    wr16(lp + 4, l.in);
    wr16(lp + 6, l.out);
  }
  for (uint32_t i = 0; i < M.param_count; ++i) {
    uint32_t bits;
    std::memcpy(&bits, &M.params[i], 4);
    wr32(lp + 4 * i, bits);
  }
  wr32(out + size - 4, crc32(out, size - 4));
  return size;
}

}  // namespace nlsoft
