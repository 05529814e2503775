#pragma once
// A model's shape and the shapes a firmware accepts (RIG_INFO, protocol
// 1.2) in words, and the refusal of a model file the firmware would not
// take, said before a byte of it is sent:
//   "model.nlsm is Dense 36->10->5->3; this firmware (rig hasel) accepts
//    Dense 36->5->5->3 only"
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "protocol/rig_shapes.hpp"

namespace nlsoft::console {

// "Dense 36->5->5->3"; with a GRU layer each layer is named:
// "21->GRU(5)->Dense(5)->Dense(3)". p is the network's input length.
std::string shape_words(const protocol::WireShape& s, int p);

// What `rig` accepts: "Dense 36->5->5->3 only", "A or B only", "any shape
// within 8 layers, 48 wide, 8192 weights".
std::string accepted_words(const protocol::RigInfo& rig);

// Why a firmware that sent `rig` would refuse the model file `bytes` (named
// `file` in the words) for its shape; nothing when it takes it, when the
// bytes do not start with a model header, or when m, n or w differ (a model
// for another plant: the caller says so in its own words).
std::optional<std::string> shape_refusal(const std::string& file, const std::vector<uint8_t>& bytes,
                                         const protocol::RigInfo& rig);

}  // namespace nlsoft::console
