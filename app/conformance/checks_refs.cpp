// REF_SELECT (PROTOCOL.md 7, 9.3): each built-in reference accepted, every
// refusal naming its field and element, refusals changing nothing, and the
// fields a reference does not use ignored whatever they hold.
#include <fmt/format.h>

#include <limits>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

p::RefSelect valid(p::RefId id) {
  p::RefSelect r;
  r.ref_id = uint8_t(id);
  r.hold = 10;
  r.a = r.b = r.c = 0.1f;
  r.omega = 0.01f;
  r.lambda = 200.0f;
  r.scale = 0.1f;
  r.level_count = 3;
  r.levels[0] = 0.1f, r.levels[1] = 0.2f, r.levels[2] = 0.3f;
  return r;
}

}  // namespace

void check_references(Suite& s) {
  s.group("references");
  if (!(s.info.info.capabilities & p::capability::kRefBuiltin)) {
    s.check("ref_select", true, "no REF_BUILTIN capability: nothing to try");
    return;
  }
  std::vector<std::string> bad;
  for (p::RefId id : {p::RefId::Infinity, p::RefId::Pringle, p::RefId::Diagonal, p::RefId::Swirl, p::RefId::Step,
                      p::RefId::Hold}) {
    const Frame f = s.pr.request(valid(id));
    if (!acked(f, p::MsgType::RefSelect)) bad.push_back(fmt::format("ref_id {}: {}", int(id), describe(f)));
  }
  s.check("ref_select", bad.empty(), bad.empty() ? "each built-in reference but table accepted" : join(bad, "; "));

  // Refusals, from a known reference in force (hold), which must stay.
  s.pr.request(valid(p::RefId::Hold));
  struct Case {
    const char* what;
    p::RefSelect msg;
    p::StatusCode status;
    uint8_t field, element;
  };
  std::vector<Case> cases;
  auto add = [&](const char* what, p::RefId id, auto edit, p::StatusCode st, uint8_t field, uint8_t element) {
    p::RefSelect m = valid(id);
    edit(m);
    cases.push_back({what, m, st, field, element});
  };
  const uint8_t none = p::kNoField;
  add("ref_id 7", p::RefId::Hold, [](p::RefSelect& m) { m.ref_id = 7; }, p::StatusCode::UnknownId, 0, none);
  add("infinity a=NaN", p::RefId::Infinity, [](p::RefSelect& m) { m.a = kNaN; }, p::StatusCode::NotFinite, 3, none);
  add("pringle center[2]=Inf", p::RefId::Pringle, [](p::RefSelect& m) { m.center[2] = kInf; },
      p::StatusCode::NotFinite, 6, 2);
  add("infinity omega=NaN", p::RefId::Infinity, [](p::RefSelect& m) { m.omega = kNaN; }, p::StatusCode::NotFinite, 7,
      none);
  add("swirl scale=-Inf", p::RefId::Swirl, [](p::RefSelect& m) { m.scale = -kInf; }, p::StatusCode::NotFinite, 9, none);
  add("step levels[1]=NaN", p::RefId::Step, [](p::RefSelect& m) { m.levels[1] = kNaN; }, p::StatusCode::NotFinite, 10, 1);
  add("step level_count=4", p::RefId::Step, [](p::RefSelect& m) { m.level_count = 4; }, p::StatusCode::OutOfRange, 1,
      none);
  add("step level_count=0", p::RefId::Step, [](p::RefSelect& m) { m.level_count = 0; }, p::StatusCode::OutOfRange, 1,
      none);
  add("diagonal lambda=0", p::RefId::Diagonal, [](p::RefSelect& m) { m.lambda = 0; }, p::StatusCode::OutOfRange, 8, none);
  add("pringle lambda=-1", p::RefId::Pringle, [](p::RefSelect& m) { m.lambda = -1; }, p::StatusCode::OutOfRange, 8, none);
  add("pringle A with B=0", p::RefId::Pringle, [](p::RefSelect& m) { m.b = 0; }, p::StatusCode::Inconsistent, 4, none);
  for (const Case& c : cases) {
    const Frame f = s.pr.request(c.msg);
    const auto st = s.status();
    const bool kept = st && st->ref_id == uint8_t(p::RefId::Hold);
    s.check(fmt::format("ref_refused {}", c.what), nacked(f, c.status, c.field, c.element) && kept,
            fmt::format("{}: {} (expected {} field {} element {}); reference in force {}", c.what, describe(f),
                        status_words(uint8_t(c.status)), c.field, c.element,
                        !st ? "unknown" : kept ? "unchanged" : fmt::format("CHANGED to {}", st->ref_id)));
  }

  // Fields the reference does not use are ignored, NaN included.
  {
    p::RefSelect m = valid(p::RefId::Infinity);
    m.lambda = kNaN;
    m.scale = kInf;
    m.levels[0] = kNaN;
    const Frame f = s.pr.request(m);
    const auto st = s.status();
    s.check("ref_unused_ignored", acked(f, p::MsgType::RefSelect) && st && st->ref_id == uint8_t(p::RefId::Infinity),
            "infinity with lambda NaN, scale Inf, levels[0] NaN: " + describe(f));
  }
  {
    p::RefSelect m = valid(p::RefId::Step);
    m.level_count = 1;
    m.levels[1] = kNaN;
    m.levels[2] = kInf;
    const Frame f = s.pr.request(m);
    s.check("ref_levels_past_count_ignored", acked(f, p::MsgType::RefSelect),
            "step with level_count 1, levels[1] NaN, levels[2] Inf: " + describe(f));
  }
  s.pr.request(valid(p::RefId::Hold));
}

}  // namespace nlsoft::console::conformance
