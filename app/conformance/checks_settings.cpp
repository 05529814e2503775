// Settings (PROTOCOL.md 7 SETTINGS, 9.11; protocol 1.5): with the SETTINGS
// capability, `report` answered ACK and an action past `report` refused
// `out_of_range` on field 0. Nothing is saved or restored: the suite
// leaves the firmware's flash as it found it. The capability is optional
// (a board without a settings store clears it), so its absence passes.
#include <fmt/format.h>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

void check_settings(Suite& s) {
  s.group("settings");
  if (!(s.info.info.capabilities & p::capability::kSettings)) {
    s.check("settings", true,
            fmt::format("protocol 1.{} without the SETTINGS capability: the firmware keeps no settings (optional)",
                        s.info.protocol_minor));
    return;
  }
  std::vector<std::string> faults;
  p::Settings report;
  report.action = uint8_t(p::SettingsAction::Report);
  const Frame r = s.pr.request(report);
  p::Ack ack;
  if (!as(r, ack) || ack.request_type != uint8_t(p::MsgType::Settings))
    faults.push_back(fmt::format("report answered by {}", describe(r)));
  p::Settings bad;
  bad.action = 3;
  const Frame b = s.pr.request(bad);
  p::Nack n;
  if (!as(b, n) || n.status != uint8_t(p::StatusCode::OutOfRange) || n.field != 0)
    faults.push_back(fmt::format("action 3 answered by {} (out_of_range, field 0 expected)", describe(b)));
  s.check("settings", faults.empty(),
          faults.empty() ? "report ACKed, action 3 refused out_of_range on field 0" : join(faults, "; "));
}

}  // namespace nlsoft::console::conformance
