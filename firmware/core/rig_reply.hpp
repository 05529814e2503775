#pragma once
// RIG_INFO (protocol 1.2) and the model shape checks that follow from it,
// apart from the core's request loop: what the image says it accepts is
// what XFER_BEGIN and the model's header chunk are held to, from the same
// compile-time list (Cap::Shapes / Cap::generic) the kernels come from.
#include <cstring>

#include "protocol/messages.hpp"
#include "protocol/rig_shapes.hpp"
#include "protocol/transfer.hpp"

namespace nlsoft::fw {

// `dims` is whatever holds the rig's m, n, w, nd and dd (a RigConfig).
// `as_list`: a shape list even from a generic kernel (fill_accepted_shapes).
template <class Cap, class Dims>
protocol::RigInfo rig_info(const char* rig_name, uint32_t rig_hash, const Dims& p, bool as_list = false) {
  protocol::RigInfo r;
  r.rig_hash = rig_hash;
  std::strncpy(r.rig_name, rig_name ? rig_name : "", protocol::kRigNameLen);
  r.m = uint8_t(p.m), r.n = uint8_t(p.n), r.w = uint8_t(p.w), r.nd = uint8_t(p.nd), r.dd = uint8_t(p.dd);
  // A list that does not fit the message would be a build mistake; an empty
  // list then says "no model accepted" rather than something untrue.
  if (!protocol::fill_accepted_shapes<Cap>(r, as_list)) r.shapes_size = 0;
  return r;
}

// XFER_BEGIN of a model: a size no listed shape can have is refused
// (`unsupported`, field 2) before the transfer opens.
inline bool model_size_refused(const protocol::RigInfo& rig, const protocol::XferBegin& b) {
  return b.kind == uint8_t(protocol::XferKind::Model) && !protocol::size_fits_a_shape(rig, b.total_size);
}

// After a model chunk was stored: once the staged bytes first cover the
// file's header and layer table (`before` is next_offset before the chunk),
// the shape they name. Ok while they are not all there, and after.
inline protocol::StatusCode model_header_verdict(const protocol::RigInfo& rig, const protocol::TransferReceiver& rx,
                                                 uint32_t before) {
  const uint32_t have = rx.next_offset();
  if (have <= model_offset::kLayers || std::memcmp(rx.data(), "NLSM", 4) != 0) return protocol::StatusCode::Ok;
  const uint32_t need = uint32_t(kModelHeaderSize + kModelLayerSize * rx.data()[model_offset::kLayers]);
  if (before >= need || have < need) return protocol::StatusCode::Ok;
  const uint8_t* f = rx.data();
  namespace at = model_offset;
  const bool dims = f[at::kM] == rig.m && f[at::kN] == rig.n && f[at::kW] == rig.w;
  // More layers than a shape list can name is more than max_layers too:
  // refused here like any shape beyond the limits, never left to COMMIT's
  // too_large (PROTOCOL.md 9.4).
  if (f[at::kLayers] > protocol::kMaxShapeLayers)
    return dims ? protocol::StatusCode::Unsupported : protocol::StatusCode::Inconsistent;
  protocol::ModelShape s;
  if (!protocol::model_shape(f, have, s)) return protocol::StatusCode::Ok;  // no layer: COMMIT names it
  switch (protocol::accepts(rig, s)) {
    case protocol::ShapeVerdict::Accepted: return protocol::StatusCode::Ok;
    case protocol::ShapeVerdict::OtherDims: return protocol::StatusCode::Inconsistent;
    default: return protocol::StatusCode::Unsupported;
  }
}

}  // namespace nlsoft::fw
