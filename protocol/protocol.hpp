#pragma once
// Everything a peer needs: frame constants, catalogue, messages, encoder,
// decoder. Include the individual headers to keep compile units lean.

#include "protocol/byte_io.hpp"
#include "protocol/catalog.hpp"
#include "protocol/cobs.hpp"
#include "protocol/crc.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "protocol/frame.hpp"
#include "protocol/messages.hpp"
#include "protocol/reply_cache.hpp"
#include "protocol/rig_shapes.hpp"
#include "protocol/status.hpp"
#include "protocol/transfer.hpp"
