#include "app/link/link_error.hpp"

#include <fmt/format.h>

#include "protocol/catalog.hpp"

namespace nlsoft::console {

namespace {

// Walks a message's field list (the same list pack/unpack use) and keeps the
// name of field #target, so NACK field numbers are never mapped by hand.
struct FieldNamer {
  unsigned target;
  unsigned index = 0;
  const char* found = nullptr;
  void hit(const char* name) {
    if (index++ == target) found = name;
  }
  template <class T> void u8(const char* n, T&) { hit(n); }
  template <class T> void u16(const char* n, T&) { hit(n); }
  template <class T> void u32(const char* n, T&) { hit(n); }
  template <class T> void f32(const char* n, T&) { hit(n); }
  template <class T> void nibbles(const char* a, T&, const char* b, T&) { hit(a), hit(b); }
  template <class A, class C> void f32_array(const char* n, A&, C, uint8_t) { hit(n); }
  template <class A, class C> void f32_tail(const char* n, A&, C&, uint8_t) { hit(n); }
  template <class A, class C, class P> void word_tail(const char* n, A&, C&, uint8_t, P) { hit(n); }
  template <class A, class C> void bytes_tail(const char* n, A&, C&, uint8_t) { hit(n); }
  template <class A> void text_tail(const char* n, A&, uint8_t) { hit(n); }
  template <class A> void text_fixed(const char* n, A&, uint8_t) { hit(n); }
};

}  // namespace

std::string status_words(uint8_t status) {
  using protocol::StatusCode;
  switch (StatusCode(status)) {
    case StatusCode::Ok: return "ok";
    case StatusCode::OutOfRange: return "out of range";
    case StatusCode::NotFinite: return "not a finite number";
    case StatusCode::WrongSize: return "wrong number of values";
    case StatusCode::UnknownId: return "unknown id";
    case StatusCode::Inconsistent: return "inconsistent with other parameters";
    case StatusCode::TooLarge: return "too large for this firmware";
    case StatusCode::BadFormat: return "content failed validation";
    case StatusCode::BadChecksum: return "checksum mismatch";
    case StatusCode::BadLength: return "malformed request";
    case StatusCode::Unsupported: return "not supported by this firmware";
    case StatusCode::ReadOnly: return "read-only";
    case StatusCode::WrongState: return "not allowed in the current run state";
    case StatusCode::Busy: return "busy (another transfer is open)";
    case StatusCode::XferNotOpen: return "no transfer open";
    case StatusCode::XferIncomplete: return "transfer incomplete";
    case StatusCode::Internal: return "internal firmware error";
  }
  return fmt::format("failed (status {})", status);
}

std::string message_name(uint8_t type) {
  if (protocol::find_message(type) == nullptr) return fmt::format("type 0x{:02X}", type);
  return protocol::message_name(type);
}

std::string request_field_name(uint8_t request_type, uint8_t field) {
  FieldNamer namer{field};
  const bool known = protocol::with_message_type(request_type, [&](auto msg) {
    using M = decltype(msg);
    M::fields(msg, namer);
  });
  if (!known || namer.found == nullptr) return fmt::format("field {}", field);
  return namer.found;
}

std::string describe_nack(const protocol::Nack& nack) {
  std::string where;
  if (nack.field != protocol::kNoField) {
    where = request_field_name(nack.request_type, nack.field);
    if (nack.element != protocol::kNoField) where += fmt::format("[{}]", nack.element);
    where = " (" + where + ")";
  }
  return fmt::format("{} refused: {}{}", message_name(nack.request_type), status_words(nack.status), where);
}

}  // namespace nlsoft::console
