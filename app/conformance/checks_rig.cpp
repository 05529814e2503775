// The rig on the wire (PROTOCOL.md 7 RIG_GET/RIG_INFO, 9.4; protocol 1.2):
// the rig's name and hash, dimensions that agree with INFO, a shape list
// that makes sense for them, and the firmware's own refusal of a model of a
// shape it does not accept, at XFER_BEGIN or at the chunk that brings the
// header, before the commit.
#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "app/conformance/suite.hpp"
#include "protocol/crc.hpp"
#include "protocol/rig_shapes.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::console::conformance {

namespace {

constexpr uint8_t kModel = uint8_t(p::XferKind::Model);

int input_length(const p::RigInfo& r) { return int(r.nd) * r.m + int(r.dd) * r.n + r.w; }

// What is wrong with rig_name's 24 raw bytes (offset 4 of the payload).
std::string name_fault(const std::vector<uint8_t>& payload) {
  size_t len = 0;
  while (len < p::kRigNameLen && payload[4 + len] != 0) ++len;
  if (len == 0) return "empty";
  for (size_t i = 0; i < len; ++i) {
    const uint8_t c = payload[4 + i];
    if (c < 0x21 || c > 0x7E) return fmt::format("byte {} is 0x{:02x}, not printable", i, c);
  }
  for (size_t i = len; i < p::kRigNameLen; ++i)
    if (payload[4 + i] != 0) return fmt::format("byte {} after the terminating NUL is 0x{:02x}", i, payload[4 + i]);
  return "";
}

// What is inconsistent in the shape list of `r` (empty when nothing).
std::vector<std::string> shape_faults(const p::RigInfo& r) {
  std::vector<std::string> bad;
  if (r.max_layers == 0 || r.max_width == 0 || r.max_weights == 0)
    bad.push_back(fmt::format("limits {} layers, {} wide, {} weights", r.max_layers, r.max_width, r.max_weights));
  if (r.accept == p::shape_accept::kAny) {
    if (r.shapes_size != 0) bad.push_back("accept 1 (any) with a shape list");
    return bad;
  }
  if (r.accept != p::shape_accept::kList) bad.push_back(fmt::format("accept {}", r.accept));
  if (!p::shapes_well_formed(r.shapes, r.shapes_size)) return bad.push_back("malformed shape list"), bad;
  if (r.shapes_size == 0) bad.push_back("accept 0 (a list) with no shape");
  size_t pos = 0;
  p::WireShape s;
  for (int k = 0; p::next_shape(r.shapes, r.shapes_size, pos, s); ++k) {
    uint32_t in = uint32_t(input_length(r)), weights = 0;
    for (uint8_t l = 0; l < s.layers; ++l) {
      const LayerKind kind = LayerKind(s.kind[l]);  // a well-formed list names known kinds
      const uint32_t u = s.units[l], cols = layer_columns(kind, u);
      weights += layer_weights(kind, in, u, true);
      if (cols > r.max_width) bad.push_back(fmt::format("shape {} layer {}: {} wide > max_width", k, l, cols));
      in = u;
    }
    if (s.units[s.layers - 1] != r.n) bad.push_back(fmt::format("shape {} ends in {} units, n is {}", k, in, r.n));
    if (s.layers > r.max_layers) bad.push_back(fmt::format("shape {}: {} layers > max_layers", k, s.layers));
    // A GRU's weights depend on reset_after; counted with two bias rows, the most.
    if (weights > r.max_weights) bad.push_back(fmt::format("shape {}: {} weights > max_weights", k, weights));
  }
  return bad;
}

// A whole model file (zero weights) of these dense layers for the rig's
// dimensions: what the refusal check uploads.
std::vector<uint8_t> dense_model(const p::RigInfo& r, const std::vector<uint32_t>& units) {
  const uint32_t p0 = uint32_t(input_length(r));
  uint32_t params = 2 * p0 + 2 * uint32_t(r.n), in = p0;
  for (uint32_t u : units) params += in * u + u, in = u;
  std::vector<uint8_t> f(model_file_size(int(units.size()), params), 0);
  std::memcpy(f.data(), "NLSM", 4);
  namespace at = model_offset;
  f[at::kVersion] = kModelFormatVersion;
  f[at::kM] = r.m, f[at::kN] = r.n, f[at::kW] = r.w, f[at::kNd] = r.nd, f[at::kDd] = r.dd;
  f[at::kLayers] = uint8_t(units.size());
  f[at::kPlatform] = 255;
  for (int i = 0; i < 4; ++i) f[at::kParams + i] = uint8_t(params >> (8 * i));
  in = p0;
  for (size_t l = 0; l < units.size(); ++l) {
    uint8_t* e = f.data() + kModelHeaderSize + kModelLayerSize * l;
    e[0] = p::kShapeDense;
    e[4] = uint8_t(in), e[5] = uint8_t(in >> 8), e[6] = uint8_t(units[l]), e[7] = uint8_t(units[l] >> 8);
    in = units[l];
  }
  const uint32_t crc = p::crc32(f.data(), f.size() - 4);
  for (int i = 0; i < 4; ++i) f[f.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
  return f;
}

// A model the firmware must refuse for its shape: the first listed shape
// with a first layer one unit narrower (as Dense layers; an image's
// model_max is often its one shape's size, so not wider), or, with accept =
// any, a first layer one unit wider than max_width.
std::vector<uint8_t> refused_model(const p::RigInfo& r) {
  std::vector<uint32_t> units;
  if (r.accept == p::shape_accept::kAny) {
    units = {uint32_t(r.max_width) + 1, r.n};
  } else {
    size_t pos = 0;
    p::WireShape s;
    if (!p::next_shape(r.shapes, r.shapes_size, pos, s)) return {};
    for (uint8_t l = 0; l < s.layers; ++l) units.push_back(s.units[l]);
    if (units.size() == 1) units.insert(units.begin(), 1);  // one more layer: another shape too
    else if (units[0] > 1) units[0] -= 1;
    else units[0] += 1;
  }
  return dense_model(r, units);
}

// A file of the size of the first listed shape (with accept = any, a
// single Dense layer of n units), its header naming that shape with m + 1:
// a size BEGIN lets in, a header of another plant. Zero weights.
std::vector<uint8_t> other_plant(const p::RigInfo& r) {
  p::WireShape s;
  size_t pos = 0;
  if (r.accept != p::shape_accept::kList || !p::next_shape(r.shapes, r.shapes_size, pos, s)) {
    s = p::WireShape{};
    s.layers = 1, s.kind[0] = p::kShapeDense, s.units[0] = r.n;
  }
  std::vector<uint8_t> f(p::model_file_sizes(r, s).min, 0);
  const uint32_t params = uint32_t((f.size() - 4 - kModelHeaderSize - kModelLayerSize * s.layers) / 4);
  std::memcpy(f.data(), "NLSM", 4);
  namespace at = model_offset;
  f[at::kVersion] = kModelFormatVersion;
  f[at::kM] = uint8_t(r.m + 1), f[at::kN] = r.n, f[at::kW] = r.w, f[at::kNd] = r.nd, f[at::kDd] = r.dd;
  f[at::kLayers] = s.layers;
  f[at::kPlatform] = 255;
  for (int i = 0; i < 4; ++i) f[at::kParams + i] = uint8_t(params >> (8 * i));
  uint32_t in = uint32_t(input_length(r));
  for (uint8_t l = 0; l < s.layers; ++l) {
    uint8_t* e = f.data() + kModelHeaderSize + kModelLayerSize * l;
    e[0] = s.kind[l];
    e[4] = uint8_t(in), e[5] = uint8_t(in >> 8), e[6] = uint8_t(s.units[l]), e[7] = uint8_t(s.units[l] >> 8);
    in = s.units[l];
  }
  const uint32_t crc = p::crc32(f.data(), f.size() - 4);
  for (int i = 0; i < 4; ++i) f[f.size() - 4 + size_t(i)] = uint8_t(crc >> (8 * i));
  return f;
}

// One try at uploading `model`: BEGIN, then the chunks up to the one that
// completes the header and layer table, split after `first` bytes (0: the
// header in one chunk), stopping at the first NACK; then COMMIT (which must
// find no transfer open) and an ABORT whatever happened.
struct Upload {
  std::string refused_at;  // "XFER_BEGIN", "chunk 1", "chunk 2", or empty
  Frame refusal;           // the NACK, or the last reply when none came
  Frame commit;
  bool acked_before = true;  // every chunk before the refusal ACKed with its bytes stored
};

Upload try_upload(Suite& s, const std::vector<uint8_t>& model, size_t first) {
  Upload u;
  p::XferBegin begin;
  begin.kind = kModel;
  begin.options = p::xfer_options::kRestart;
  begin.total_size = uint32_t(model.size());
  begin.crc32 = p::crc32(model.data(), model.size());
  u.refusal = s.pr.request(begin);
  if (u.refusal.type == uint8_t(p::MsgType::Nack)) {
    u.refused_at = "XFER_BEGIN";
  } else if (u.refusal.type == uint8_t(p::MsgType::XferAck)) {
    const size_t header = kModelHeaderSize + kModelLayerSize * size_t(model[model_offset::kLayers]);
    const size_t end = std::min(header, model.size());
    size_t at = 0;
    for (int k = 1; at < end; ++k) {
      p::XferChunk c;
      c.kind = kModel;
      c.offset = uint32_t(at);
      c.size = uint8_t(std::min<size_t>(p::kMaxChunkData, first && k == 1 ? first : end - at));
      std::memcpy(c.data, model.data() + at, c.size);
      u.refusal = s.pr.request(c);
      at += c.size;
      p::XferAck ack;
      if (u.refusal.type == uint8_t(p::MsgType::Nack)) {
        u.refused_at = fmt::format("chunk {}", k);
        break;
      }
      u.acked_before = u.acked_before && as(u.refusal, ack) && ack.next_offset == at;
    }
  }
  p::XferCommit commit;
  commit.kind = kModel;
  u.commit = s.pr.request(commit);
  p::XferAbort abort;  // whatever happened, no transfer is left open
  abort.kind = kModel;
  s.pr.request(abort);
  return u;
}

// The model's first `layers` Dense layers of one unit, the last of n: the
// fewest weights for that many layers.
std::vector<uint32_t> thin_layers(const p::RigInfo& r, int layers) {
  std::vector<uint32_t> units(size_t(layers), 1);
  units.back() = r.n;
  return units;
}

// RIG_INFO's dimensions against INFO's, its name, its hash across two
// RIG_GETs and its shapes.
void check_rig_info(Suite& s, const Frame& a, const p::RigInfo& r) {
  const p::Info& i = s.info.info;
  std::vector<std::string> dims;
  if (r.m != i.m || r.n != i.n || r.w != i.w || r.nd != i.nd || r.dd != i.dd)
    dims.push_back(fmt::format("m={} n={} w={} nd={} dd={}, INFO m={} n={} w={} nd={} dd={}", r.m, r.n, r.w, r.nd,
                               r.dd, i.m, i.n, i.w, i.nd, i.dd));
  s.check("rig_info", dims.empty(),
          dims.empty() ? fmt::format("rig {}, hash {:08x}, dimensions as INFO's", r.rig_name, r.rig_hash)
                       : "RIG_INFO " + join(dims, "; "));
  const std::string name = name_fault(a.payload);
  s.check("rig_name", name.empty(),
          name.empty() ? fmt::format("\"{}\": printable, NUL-padded", r.rig_name) : "rig_name: " + name);

  const Frame b = s.pr.request(p::RigGet{});
  s.check("rig_hash_stable", b.type == a.type && b.payload == a.payload,
          b.payload == a.payload ? fmt::format("two RIG_GETs, the same RIG_INFO (hash {:08x})", r.rig_hash)
                                 : "the second RIG_GET answered " + describe(b));

  const std::vector<std::string> shapes = shape_faults(r);
  s.check("rig_shapes", shapes.empty(),
          shapes.empty()
              ? (r.accept == p::shape_accept::kAny
                     ? fmt::format("any shape within {} layers, {} wide, {} weights", r.max_layers, r.max_width,
                                   r.max_weights)
                     : fmt::format("{} listed shape{}, each ending in n={} units, within the limits",
                                   p::shape_count(r), p::shape_count(r) == 1 ? "" : "s", r.n))
              : join(shapes, "; "));
}

// The firmware's own line of defence: a model of a refused shape is
// refused before its commit, and nothing changes. False when no refused
// shape fits model_max: the model checks after it are left out too.
bool check_refused_shape(Suite& s, const p::RigInfo& r) {
  const std::vector<uint8_t> model = refused_model(r);
  if (model.empty() || (s.info.model_max && model.size() > s.info.model_max)) {
    s.check("xfer_model_shape_refused", true,
            fmt::format("no refused shape fits model_max {} (a {}-byte model): nothing to check", s.info.model_max,
                        model.size()));
    return false;
  }
  const auto was = s.info_now();
  const Upload u = try_upload(s, model, 0);
  const auto now = s.info_now();
  const bool same = was && now && was->info.model_hash == now->info.model_hash;
  const bool closed = nacked(u.commit, p::StatusCode::XferNotOpen, 0, p::kNoField);
  // With a list, a size no listed shape has is refused before any byte
  // (9.4 BEGIN); any other refused shape at the chunk that brings its header.
  const bool by_size = r.accept == p::shape_accept::kList && !p::size_fits_a_shape(r, uint32_t(model.size()));
  const std::string expected = by_size ? "XFER_BEGIN" : "chunk 1";
  const bool refused = nacked(u.refusal, p::StatusCode::Unsupported, 2, p::kNoField) && u.refused_at == expected;
  // An accepted BEGIN puts the built-in model back in force (9.4): model_hash
  // may change then, never after a refused BEGIN.
  s.check("xfer_model_shape_refused", refused && closed && (same || u.refused_at != "XFER_BEGIN"),
          fmt::format("a model of a shape RIG_INFO does not accept ({} bytes{}): {}; XFER_COMMIT after it: {}; "
                      "model_hash {}",
                      model.size(), by_size ? ", a size no listed shape has" : "",
                      refused ? "refused at " + (by_size ? expected : std::string("the first XFER_CHUNK")) +
                                    " (unsupported, field 2)"
                              : "expected a refusal at " + expected + ", got " +
                                    (u.refused_at.empty() ? "none" : "one at " + u.refused_at) + ": " +
                                    describe(u.refusal),
                      describe(u.commit), same ? "unchanged" : "changed"));
  return true;
}

// A header split over two chunks is judged at the chunk that completes
// it, not at the one at offset 0: here a header of another plant (m + 1)
// in a file of an accepted size, cut after its layer count.
void check_header_split(Suite& s, const p::RigInfo& r) {
  const std::vector<uint8_t> other = other_plant(r);
  if (s.info.model_max && other.size() > s.info.model_max) {
    s.check("xfer_model_header_split", true,
            fmt::format("a {}-byte model is above model_max {}: nothing to check", other.size(), s.info.model_max));
  } else {
    const size_t cut = model_offset::kLayers + 1;
    const Upload v = try_upload(s, other, cut);
    const bool ok = v.refused_at == "chunk 2" && v.acked_before &&
                    nacked(v.refusal, p::StatusCode::Inconsistent, 2, p::kNoField) &&
                    nacked(v.commit, p::StatusCode::XferNotOpen, 0, p::kNoField);
    s.check("xfer_model_header_split", ok,
            fmt::format("a header naming m={} (INFO m={}) sent as {} bytes, then the rest of its {}: {}{}; "
                        "XFER_COMMIT after it: {}",
                        other[model_offset::kM], s.info.info.m, cut,
                        kModelHeaderSize + kModelLayerSize * size_t(other[model_offset::kLayers]),
                        v.refused_at.empty() ? "not refused" : "refused at " + v.refused_at + ": ",
                        describe(v.refusal), describe(v.commit)));
  }
}

// More layers than max_layers: unsupported (field 2), at BEGIN by its
// size or at its header, never left to COMMIT (where it would be
// too_large).
void check_too_many_layers(Suite& s, const p::RigInfo& r) {
  const std::vector<uint8_t> deep = dense_model(r, thin_layers(r, r.max_layers + 1));
  if (s.info.model_max && deep.size() > s.info.model_max) {
    s.check("xfer_model_too_many_layers", true,
            fmt::format("a model of {} layers is {} bytes, above model_max {}: nothing to check", r.max_layers + 1,
                        deep.size(), s.info.model_max));
  } else {
    const Upload v = try_upload(s, deep, 0);
    const bool ok = (v.refused_at == "XFER_BEGIN" || v.refused_at == "chunk 1") &&
                    nacked(v.refusal, p::StatusCode::Unsupported, 2, p::kNoField) &&
                    nacked(v.commit, p::StatusCode::XferNotOpen, 0, p::kNoField);
    s.check("xfer_model_too_many_layers", ok,
            fmt::format("a model of {} layers (max_layers {}): {}{}; XFER_COMMIT after it: {}", r.max_layers + 1,
                        r.max_layers, v.refused_at.empty() ? "not refused: " : "refused at " + v.refused_at + ": ",
                        describe(v.refusal), describe(v.commit)));
  }
}

}  // namespace

void check_rig(Suite& s) {
  s.group("rig");
  if (!s.offers(p::capability::kRig, "RIG", 2, "rig_info", "no RIG_INFO to check")) return;
  const Frame a = s.pr.request(p::RigGet{});
  p::RigInfo r;
  if (!as(a, r)) {
    s.check("rig_info", false, "RIG_GET answered by " + describe(a));
    return;
  }
  check_rig_info(s, a, r);
  if (!(s.info.info.capabilities & p::capability::kXferModel)) return;
  if (!check_refused_shape(s, r)) return;
  check_header_split(s, r);
  check_too_many_layers(s, r);
}

}  // namespace nlsoft::console::conformance
