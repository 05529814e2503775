// Transfers (PROTOCOL.md 9.4) with reference tables (kind 1): a lost chunk
// heals, a transfer interrupted at each stage leaves the previous table in
// force and can be resumed or is refused as it should, and every refusal
// names its field.
#include <fmt/format.h>

#include <cstring>

#include "app/conformance/suite.hpp"
#include "protocol/crc.hpp"

namespace nlsoft::console::conformance {

namespace {

constexpr uint8_t kTable = uint8_t(p::XferKind::RefTable);
constexpr uint32_t kChunk = 32;

std::vector<uint8_t> table(uint8_t n, uint32_t count, float scale = 0.01f) {
  std::vector<uint8_t> o(8 + 4u * n * count, 0);
  o[0] = 1;
  o[1] = n;
  std::memcpy(&o[4], &count, 4);
  for (uint32_t k = 0; k < count * n; ++k) {
    const float x = scale * float(k % 7);
    std::memcpy(&o[8 + 4 * k], &x, 4);
  }
  return o;
}

Frame begin(Suite& s, uint32_t size, uint32_t crc, uint8_t options = p::xfer_options::kRestart, uint8_t kind = kTable) {
  p::XferBegin b;
  b.kind = kind;
  b.options = options;
  b.total_size = size;
  b.crc32 = crc;
  return s.pr.request(b);
}

// size 0: up to kChunk bytes, within the object.
Frame chunk(Suite& s, const std::vector<uint8_t>& obj, uint32_t offset, uint32_t size = 0) {
  if (size == 0) size = std::min<uint32_t>(kChunk, offset < obj.size() ? uint32_t(obj.size()) - offset : 1);
  p::XferChunk c;
  c.kind = kTable;
  c.offset = offset;
  c.size = uint8_t(size);  // may run past the object: the refusal is what a check wants then
  if (offset < obj.size()) std::memcpy(c.data, obj.data() + offset, std::min<size_t>(c.size, obj.size() - offset));
  return s.pr.request(c);
}

Frame commit(Suite& s, uint8_t kind = kTable) {
  p::XferCommit c;
  c.kind = kind;
  return s.pr.request(c);
}

Frame abort_xfer(Suite& s) {
  p::XferAbort a;
  a.kind = kTable;
  return s.pr.request(a);
}

uint32_t next_of(const Frame& f) {
  p::XferAck a;
  return as(f, a) ? a.next_offset : 0xFFFFFFFFu;
}

// Sends chunks from `from` until `upto` (or the end); returns next_offset.
uint32_t send(Suite& s, const std::vector<uint8_t>& obj, uint32_t from, uint32_t upto, std::string& err) {
  uint32_t next = from;
  for (int guard = 0; next < upto && next < obj.size(); ++guard) {
    if (guard > 2000) {
      err = "XFER_ACK next_offset does not advance";
      return next;
    }
    const Frame f = chunk(s, obj, next, std::min<uint32_t>({kChunk, upto - next, uint32_t(obj.size()) - next}));
    if (next_of(f) == 0xFFFFFFFFu) {
      err = fmt::format("CHUNK at {}: {}", next, describe(f));
      return next;
    }
    next = next_of(f);
  }
  return next;
}

// The table in force answers: selecting it is ACKed.
bool table_in_force(Suite& s) {
  p::RefSelect r;
  r.ref_id = uint8_t(p::RefId::Table);
  r.hold = 1;
  return acked(s.pr.request(r), p::MsgType::RefSelect);
}


// A lost chunk heals: the chunk after the gap is ignored.
void check_heal(Suite& s, const std::vector<uint8_t>& obj, uint32_t crc) {
  std::string err;
  Frame b = begin(s, uint32_t(obj.size()), crc);
  uint32_t next = next_of(b);
  if (next != 0) {
    s.check("xfer_heal", false, "XFER_BEGIN: " + describe(b));
  } else {
    next = next_of(chunk(s, obj, 0));
    const uint32_t after_gap = next_of(chunk(s, obj, 2 * kChunk));
    next = send(s, obj, after_gap, uint32_t(obj.size()), err);
    const Frame c = commit(s);
    s.check("xfer_heal", err.empty() && after_gap == kChunk && acked(c, p::MsgType::XferCommit),
            err.empty() ? fmt::format("{}-byte table: chunk at {} skipped, chunk at {} answered next_offset {}; resent "
                                      "from there, COMMIT: {}",
                                      obj.size(), kChunk, 2 * kChunk, after_gap, describe(c))
                        : err);
  }
}

// A chunk sent twice (its XFER_ACK lost) is stored once.
void check_duplicate_chunk(Suite& s, const std::vector<uint8_t>& obj, uint32_t crc) {
  begin(s, uint32_t(obj.size()), crc);
  const uint32_t a = next_of(chunk(s, obj, 0));
  const uint32_t b = next_of(chunk(s, obj, 0));
  s.check("xfer_duplicate_chunk", a == kChunk && b == kChunk,
          fmt::format("chunk at 0 twice: next_offset {} then {}", a, b));
  abort_xfer(s);
}

// Interrupted after BEGIN, mid-way and before COMMIT: resumable by a
// BEGIN of the same object; the table in force stays until COMMIT.
void check_resume(Suite& s, uint8_t n) {
  const std::vector<uint8_t> other = table(n, 16, 0.02f);
  const uint32_t ocrc = p::crc32(other.data(), other.size());
  const uint32_t r0 = next_of(begin(s, uint32_t(other.size()), ocrc));
  const uint32_t r1 = next_of(begin(s, uint32_t(other.size()), ocrc, 0));  // resumed at once
  std::string err;
  const uint32_t mid = send(s, other, 0, 2 * kChunk, err);
  const uint32_t r2 = next_of(begin(s, uint32_t(other.size()), ocrc, 0));  // resumed mid-way
  const bool kept = table_in_force(s);
  const Frame early = commit(s);
  const uint32_t last = send(s, other, r2, uint32_t(other.size()) - 1, err);
  const Frame early2 = commit(s);
  const uint32_t r3 = next_of(begin(s, uint32_t(other.size()), ocrc, 0));  // resumed before the last byte
  send(s, other, r3, uint32_t(other.size()), err);
  const Frame done = commit(s);
  const bool ok = err.empty() && r0 == 0 && r1 == 0 && mid == 2 * kChunk && r2 == mid && kept &&
                  nacked(early, p::StatusCode::XferIncomplete, p::kNoField, p::kNoField) &&
                  nacked(early2, p::StatusCode::XferIncomplete, p::kNoField, p::kNoField) &&
                  r3 == last && acked(done, p::MsgType::XferCommit);
  s.check("xfer_resume", ok,
          fmt::format("BEGIN {} then again {}; {} bytes sent, BEGIN again resumes at {}; previous table {}; COMMIT "
                      "early: {}; at {} of {} bytes: {}, BEGIN resumes at {}; COMMIT: {}{}",
                      r0, r1, mid, r2, kept ? "still in force" : "GONE", describe(early), last, other.size(),
                      describe(early2), r3, describe(done), err.empty() ? "" : "; " + err));
}

// RESTART starts over; ABORT discards; a CHUNK or COMMIT with nothing
// open is xfer_not_open.
void check_restart_abort(Suite& s, const std::vector<uint8_t>& obj, uint32_t crc) {
  begin(s, uint32_t(obj.size()), crc);
  std::string err;
  send(s, obj, 0, kChunk, err);
  const uint32_t restarted = next_of(begin(s, uint32_t(obj.size()), crc, p::xfer_options::kRestart));
  const Frame ab = abort_xfer(s);
  const Frame ab2 = abort_xfer(s);
  const Frame ch = chunk(s, obj, 0);
  const Frame co = commit(s);
  s.check("xfer_restart_abort", restarted == 0 && acked(ab, p::MsgType::XferAbort) && acked(ab2, p::MsgType::XferAbort) &&
                                    nacked(ch, p::StatusCode::XferNotOpen, 0, p::kNoField) &&
                                    (nacked(co, p::StatusCode::XferNotOpen, 0, p::kNoField) ||
                                     nacked(co, p::StatusCode::XferNotOpen, p::kNoField, p::kNoField)),
          fmt::format("RESTART after {} bytes: next_offset {}; ABORT twice: {}, {}; then CHUNK: {}; COMMIT: {}", kChunk,
                      restarted, describe(ab), describe(ab2), describe(ch), describe(co)));
}

// BEGIN refusals.
void check_begin_refusals(Suite& s) {
  const Frame zero = begin(s, 0, 0);
  s.check("xfer_begin_empty", nacked(zero, p::StatusCode::OutOfRange, 2, p::kNoField), "total_size 0: " + describe(zero));
  const uint32_t limit = s.info.table_max;
  if (limit) {
    const Frame big = begin(s, limit + 1, 0);
    const Frame fits = begin(s, limit, 0);
    s.check("xfer_begin_too_large",
            nacked(big, p::StatusCode::TooLarge, 2, p::kNoField) && next_of(fits) == 0,
            fmt::format("total_size {} (INFO_EX table_max {}): {}; {} bytes: {}", limit + 1, limit, describe(big), limit,
                        describe(fits)));
    abort_xfer(s);
  } else {
    const Frame big = begin(s, 0x7FFFFFFFu, 0);
    s.check("xfer_begin_too_large", nacked(big, p::StatusCode::TooLarge, 2, p::kNoField),
            "total_size 2^31 - 1: " + describe(big));
  }
  const Frame kind = begin(s, 16, 0, p::xfer_options::kRestart, 9);
  s.check("xfer_begin_unknown_kind", nacked(kind, p::StatusCode::UnknownId, 0, p::kNoField) ||
                                         nacked(kind, p::StatusCode::Unsupported, 0, p::kNoField),
          "kind 9: " + describe(kind));
}

// CHUNK past the end.
void check_chunk_past_end(Suite& s, const std::vector<uint8_t>& obj, uint32_t crc) {
  begin(s, uint32_t(obj.size()), crc);
  const Frame past = chunk(s, obj, uint32_t(obj.size()) - 4, 8);
  s.check("xfer_chunk_past_end", nacked(past, p::StatusCode::OutOfRange, 1, p::kNoField),
          fmt::format("8 bytes at {} of a {}-byte object: {}", obj.size() - 4, obj.size(), describe(past)));
  abort_xfer(s);
}

// Objects that arrive whole but are wrong: discarded, the table in force stays.
void check_bad_objects(Suite& s, const std::vector<uint8_t>& obj, uint32_t crc, uint8_t n) {
  struct Bad {
    const char* name;
    std::vector<uint8_t> obj;
    uint32_t crc;
    p::StatusCode status;
  };
  std::vector<uint8_t> fmt2 = obj;
  fmt2[0] = 2;
  const std::vector<uint8_t> wrong_n = table(uint8_t(n == 3 ? 2 : n + 1), 4);
  const Bad bads[] = {
      {"xfer_bad_checksum", obj, crc ^ 1u, p::StatusCode::BadChecksum},
      {"xfer_bad_format", fmt2, p::crc32(fmt2.data(), fmt2.size()), p::StatusCode::BadFormat},
      {"xfer_inconsistent", wrong_n, p::crc32(wrong_n.data(), wrong_n.size()), p::StatusCode::Inconsistent},
  };
  for (const Bad& b : bads) {
    const Frame bf = begin(s, uint32_t(b.obj.size()), b.crc);
    std::string err;
    send(s, b.obj, 0, uint32_t(b.obj.size()), err);
    const Frame c = commit(s);
    const Frame again = commit(s);
    const bool kept = table_in_force(s);
    p::Nack nk;
    const bool refused = as(c, nk) && nk.status == uint8_t(b.status);
    s.check(b.name, next_of(bf) == 0 && err.empty() && refused &&
                        (nacked(again, p::StatusCode::XferNotOpen, 0, p::kNoField) ||
                         nacked(again, p::StatusCode::XferNotOpen, p::kNoField, p::kNoField)) &&
                        kept,
            fmt::format("COMMIT: {} (expected {}); COMMIT again: {}; previous table {}{}", describe(c),
                        status_words(uint8_t(b.status)), describe(again), kept ? "still in force" : "GONE",
                        err.empty() ? "" : "; " + err));
  }
}

// A refused model BEGIN changes nothing: the model in force stays, even on
// an MCU whose accepted model BEGIN would put its built-in model back.
void check_model_begin_too_large(Suite& s) {
  if (!((s.info.info.capabilities & p::capability::kXferModel) && s.info.model_max)) return;
  const auto was = s.info_now();
  const Frame big = begin(s, s.info.model_max + 1, 0, p::xfer_options::kRestart, uint8_t(p::XferKind::Model));
  const auto now = s.info_now();
  const bool same = was && now && was->info.model_hash == now->info.model_hash;
  s.check("xfer_model_begin_too_large", nacked(big, p::StatusCode::TooLarge, 2, p::kNoField) && same,
          fmt::format("model of {} bytes (INFO_EX model_max {}): {}; model_hash {}", s.info.model_max + 1,
                      s.info.model_max, describe(big), same ? "unchanged" : "CHANGED"));
}

}  // namespace

void check_transfers(Suite& s) {
  s.group("transfers");
  if (!(s.info.info.capabilities & p::capability::kXferModel))
    s.left_out("xfer_model_left_out", "model uploads",
               begin(s, 64, 0, p::xfer_options::kRestart, uint8_t(p::XferKind::Model)), 0);
  if (!(s.info.info.capabilities & p::capability::kXferRefTable)) {
    s.left_out("xfer_table_left_out", "reference-table uploads", begin(s, 64, 0), 0);
    return;
  }
  const uint8_t n = s.info.info.n;
  const std::vector<uint8_t> obj = table(n, 16);
  const uint32_t crc = p::crc32(obj.data(), obj.size());
  check_heal(s, obj, crc);
  check_duplicate_chunk(s, obj, crc);
  check_resume(s, n);
  check_restart_abort(s, obj, crc);
  check_begin_refusals(s);
  check_chunk_past_end(s, obj, crc);
  check_bad_objects(s, obj, crc, n);
  check_model_begin_too_large(s);
  // Leave the reference as the references group did.
  p::RefSelect hold;
  hold.ref_id = uint8_t(p::RefId::Hold);
  s.pr.request(hold);
}

}  // namespace nlsoft::console::conformance
