// Parameters (PROTOCOL.md 9.2): the list and its hash, reads, and every
// refusal of PARAM_SET with the field and element it names, each leaving
// the value as it was.
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "app/conformance/suite.hpp"
#include "protocol/crc.hpp"

namespace nlsoft::console::conformance {

namespace {

bool same(const p::ParamValue& a, const p::ParamValue& b) {
  return a.count == b.count && std::memcmp(a.values, b.values, 4u * a.count) == 0;
}

void list(Suite& s) {
  std::vector<std::string> bad;
  uint16_t count = 1;
  std::set<uint16_t> ids;
  p::Crc32 crc;
  for (uint16_t i = 0; i < count; ++i) {
    p::ParamList l;
    l.index = i;
    const Frame f = s.pr.request(l);
    p::ParamDesc d;
    if (!as(f, d)) {
      bad.push_back(fmt::format("index {}: {}", i, describe(f)));
      break;
    }
    crc.update(f.payload.data(), f.payload.size());
    if (i == 0) count = d.count;
    if (d.index != i) bad.push_back(fmt::format("index {} answered as {}", i, d.index));
    if (d.count != count) bad.push_back(fmt::format("index {}: count {} (was {})", i, d.count, count));
    if (d.size < 1 || d.size > p::kMaxParamValues) bad.push_back(fmt::format("{}: size {}", d.name, d.size));
    if (!ids.insert(d.id).second) bad.push_back(fmt::format("id {} twice", d.id));
    s.descs.push_back(d);
  }
  s.check("param_list", bad.empty() && !s.descs.empty(),
          bad.empty() ? fmt::format("{} descriptors", s.descs.size()) : join(bad, "; "));
  const uint32_t hash = s.info.info.param_hash;
  s.check("param_hash", bad.empty() && crc.value() == hash,
          fmt::format("INFO param_hash 0x{:08x}, CRC-32 of the {} PARAM_DESC payloads 0x{:08x}", hash, s.descs.size(),
                      crc.value()));
  p::ParamList l;
  l.index = count;
  const Frame f = s.pr.request(l);
  s.check("param_list_end", nacked(f, p::StatusCode::UnknownId, 0, p::kNoField),
          fmt::format("PARAM_LIST({}) answered by {}", count, describe(f)));
}

void read_all(Suite& s) {
  std::vector<std::string> bad;
  for (const p::ParamDesc& d : s.descs) {
    p::ParamGet g;
    g.id = d.id;
    const Frame f = s.pr.request(g);
    p::ParamValue v;
    if (!as(f, v)) {
      bad.push_back(fmt::format("{}: {}", d.name, describe(f)));
      continue;
    }
    if (v.id != d.id || v.count != d.size || v.type != d.type)
      bad.push_back(fmt::format("{}: id {} type {} with {} values (described id {} type {} size {})", d.name, v.id,
                                v.type, v.count, d.id, d.type, d.size));
    s.original[d.id] = v;
  }
  s.check("param_get", bad.empty(),
          bad.empty() ? fmt::format("{} parameters, each of its described size", s.descs.size()) : join(bad, "; "));
  uint16_t unused = 0xFFFF;
  while (s.original.count(unused)) --unused;
  p::ParamGet g;
  g.id = unused;
  const Frame f = s.pr.request(g);
  s.check("param_get_unknown", nacked(f, p::StatusCode::UnknownId, 0, p::kNoField),
          fmt::format("PARAM_GET({}) answered by {}", unused, describe(f)));
}

// The PARAM_SET checks need a writable f32 parameter: Q if there is one.
const p::ParamDesc* pick_f32(const Suite& s) {
  const p::ParamDesc* pick = nullptr;
  for (const p::ParamDesc& d : s.descs) {
    if (d.type != uint8_t(p::ParamType::F32) || (d.access & p::param_access::kReadOnly) || !s.original.count(d.id))
      continue;
    if (std::strcmp(d.name, "Q") == 0) return &d;
    if (!pick) pick = &d;
  }
  return pick;
}

// PARAM_SET must be NACKed with `status` at (field, element) and leave the
// parameter as it was.
void refused(Suite& s, const std::string& name, const p::ParamDesc& d, const p::ParamSet& set, p::StatusCode status,
             uint8_t field, uint8_t element, const std::string& what) {
  const Frame f = s.pr.request(set);
  const bool nack = nacked(f, status, field, element);
  const auto now = s.get(d.id);
  const bool unchanged = now && same(*now, s.original.at(d.id));
  if (!unchanged) s.touched.insert(d.id);
  s.check(name, nack && unchanged,
          fmt::format("{} {}: {} (expected field {} element {}); value read back {}", d.name, what, describe(f), field,
                      element,
                      !now ? "not readable" : unchanged ? "unchanged" : "CHANGED to " + words_text(now->values, now->count, now->type)));
}

p::ParamSet base_of(const Suite& s, const p::ParamDesc& d) {
  const p::ParamValue& orig = s.original.at(d.id);
  p::ParamSet b;
  b.id = d.id;
  b.count = orig.count;
  std::memcpy(b.values, orig.values, 4u * orig.count);
  return b;
}

// PARAM_SET of an id the firmware does not have.
void check_unknown_id(Suite& s, const p::ParamSet& base) {
  p::ParamSet x = base;
  uint16_t unused = 0xFFFF;
  while (s.original.count(unused)) --unused;
  x.id = unused;
  const Frame f = s.pr.request(x);
  s.check("param_set_unknown_id", nacked(f, p::StatusCode::UnknownId, 0, p::kNoField),
          fmt::format("PARAM_SET({}) answered by {}", unused, describe(f)));
}

// Out of range: below min (Q = -1 for Q's min 0), else above max; the
// last element, so the element index is tested too.
void check_out_of_range(Suite& s, const p::ParamDesc& d, const p::ParamSet& base) {
  const uint8_t last = uint8_t(d.size - 1);
  const float big = std::numeric_limits<float>::max() / 4;
  std::optional<float> outside;
  if (std::isfinite(d.min) && d.min > -big)
    outside = d.min - std::max(1.0f, std::fabs(d.min));
  else if (std::isfinite(d.max) && d.max < big)
    outside = d.max + std::max(1.0f, std::fabs(d.max));
  if (outside) {
    p::ParamSet x = base;
    x.set_f32(last, *outside);
    refused(s, "param_set_out_of_range", d, x, p::StatusCode::OutOfRange, 1, last,
            fmt::format("[{}] = {:g} (range {:g}..{:g})", last, *outside, d.min, d.max));
  } else {
    s.check("param_set_out_of_range", true, fmt::format("{} is unbounded: nothing to try", d.name));
  }
}

// A NaN in the last element, an infinity in the first, one value too many
// or too few: each refused naming the element, nothing applied.
void check_value_refusals(Suite& s, const p::ParamDesc& d, const p::ParamSet& base) {
  const uint8_t last = uint8_t(d.size - 1);
  {
    p::ParamSet x = base;
    x.set_f32(last, std::numeric_limits<float>::quiet_NaN());
    refused(s, "param_set_not_finite", d, x, p::StatusCode::NotFinite, 1, last, fmt::format("[{}] = NaN", last));
  }
  {
    p::ParamSet x = base;
    x.set_f32(0, std::numeric_limits<float>::infinity());
    refused(s, "param_set_infinite", d, x, p::StatusCode::NotFinite, 1, 0, "[0] = Inf");
  }
  {
    p::ParamSet x = base;
    x.count = uint8_t(d.size < p::kMaxParamValues ? d.size + 1 : d.size - 1);
    for (uint8_t i = d.size; i < x.count; ++i) x.values[i] = base.values[0];
    refused(s, "param_set_wrong_size", d, x, p::StatusCode::WrongSize, 1, p::kNoField,
            fmt::format("with {} values (size {})", x.count, d.size));
  }
}

// Refusals that depend on other parameters or on INFO: u_min above
// u_max, N above max_n, an integer word above its range.
void check_cross_refusals(Suite& s) {
  // Cross-parameter rule: u_min[i] >= u_max[i].
  if (const p::ParamDesc* umin = s.param("u_min"); umin && s.param("u_max")) {
    p::ParamSet x = base_of(s, *umin);
    const p::ParamValue& umax = s.original.at(s.param("u_max")->id);
    const uint8_t i = uint8_t(umin->size - 1);
    x.values[i] = umax.values[i];
    refused(s, "param_set_inconsistent", *umin, x, p::StatusCode::Inconsistent, 1, i,
            fmt::format("[{}] = u_max[{}] = {:g}", i, i, word_f32(umax.values[i])));
  } else {
    s.check("param_set_inconsistent", true, "no u_min/u_max pair: nothing to try");
  }
  // Capacity: N above INFO.max_n but inside its descriptor's range.
  if (const p::ParamDesc* n = s.param("N"); n && float(s.info.info.max_n) + 1 <= n->max) {
    p::ParamSet x = base_of(s, *n);
    x.values[0] = uint32_t(s.info.info.max_n) + 1;
    refused(s, "param_set_too_large", *n, x, p::StatusCode::TooLarge, 1, p::kNoField,
            fmt::format("= {} (INFO max_n {})", x.values[0], s.info.info.max_n));
  } else {
    s.check("param_set_too_large", true, "no N above max_n within its range: nothing to try");
  }
  // An integer parameter given a word above its range.
  if (const p::ParamDesc* n = s.param("N")) {
    p::ParamSet x = base_of(s, *n);
    x.values[0] = 0x10000u;
    refused(s, "param_set_integer_out_of_range", *n, x, p::StatusCode::OutOfRange, 1, 0, "= 65536");
  }
}

// A valid value: the reply is the value in force, and a read agrees.
void check_valid_set(Suite& s, const p::ParamDesc& d, const p::ParamSet& base) {
  const p::ParamValue& orig = s.original.at(d.id);
  const float now = word_f32(orig.values[0]);
  std::string tried;
  for (float c : {now * 2, now / 2, (d.min + d.max) / 2, d.min, d.max, now + 1}) {
    if (!std::isfinite(c) || c < d.min || c > d.max || f32_word(c) == orig.values[0]) continue;
    std::vector<uint32_t> words(base.values, base.values + base.count);
    words[0] = f32_word(c);
    std::string why;
    const auto echo = s.set(d, words, why);
    if (!echo) {
      tried += fmt::format(" {:g}: {};", c, why);
      continue;
    }
    const auto back = s.get(d.id);
    const bool ok = echo->id == d.id && echo->count == d.size && back && same(*back, *echo);
    s.check("param_set_valid", ok,
            fmt::format("{}[0] = {:g}: PARAM_VALUE {} in force{}; read back {}", d.name, c,
                        words_text(echo->values, echo->count, echo->type), f32_word(c) == echo->values[0] ? "" : " (adjusted)",
                        back ? words_text(back->values, back->count, back->type) : "nothing"));
    return;
  }
  s.check("param_set_valid", false, fmt::format("{}: no valid value accepted:{}", d.name, tried));
}

void refusals(Suite& s) {
  const p::ParamDesc* dp = pick_f32(s);
  if (!dp) {
    s.check("param_set_refusals", false, "no writable f32 parameter to try");
    return;
  }
  const p::ParamDesc& d = *dp;
  const p::ParamSet base = base_of(s, d);
  check_unknown_id(s, base);
  check_out_of_range(s, d, base);
  check_value_refusals(s, d, base);
  check_cross_refusals(s);
  check_valid_set(s, d, base);
}

}  // namespace

void check_params(Suite& s) {
  s.group("params");
  list(s);
  read_all(s);
  refusals(s);
}

}  // namespace nlsoft::console::conformance
