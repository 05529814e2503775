// Sensor chips (PROTOCOL.md 7 DEVICE_GET, DEVICE_STATUS; protocol 1.4): the
// list walked from index 0 to its count, each entry's fields in range, and
// the index past the last refused `unknown_id` on field 0.
#include <fmt/format.h>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

void check_devices(Suite& s) {
  s.group("devices");
  if (!s.offers(p::capability::kDevices, "DEVICES", 4, "device_list", "no sensor chips to ask about")) return;
  std::vector<std::string> faults, names;
  p::DeviceGet get;
  int count = 0;
  for (;;) {
    const Frame f = s.pr.request(get);
    p::DeviceStatus d;
    p::Nack n;
    if (as(f, n)) {
      if (n.status != uint8_t(p::StatusCode::UnknownId) || n.field != 0)
        faults.push_back(fmt::format("index {}: {}", get.index, describe(f)));
      if (get.index != count) faults.push_back(fmt::format("refused index {} of {} chips", get.index, count));
      break;
    }
    if (!as(f, d)) {
      faults.push_back(fmt::format("index {} answered by {}", get.index, describe(f)));
      break;
    }
    if (get.index == 0) count = d.count;
    if (get.index >= count) {
      faults.push_back(fmt::format("index {}, past the {} chips, answered DEVICE_STATUS", get.index, count));
      break;
    }
    if (d.index != get.index || d.count != count)
      faults.push_back(fmt::format("index {}: DEVICE_STATUS index {} count {}", get.index, d.index, d.count));
    if (d.state > uint8_t(p::DeviceState::Fault)) faults.push_back(fmt::format("index {}: state {}", get.index, d.state));
    names.push_back(fmt::format("{} {}", d.name, p::device_state_name(d.state)));
    if (!faults.empty()) break;
    get.index = uint8_t(get.index + 1);
  }
  s.devices = count;
  s.check("device_list", faults.empty(),
          faults.empty() ? fmt::format("{} chip{}{}{}", count, count == 1 ? "" : "s", names.empty() ? "" : ": ",
                                       join(names, ", "))
                         : join(faults, "; "));
}

}  // namespace nlsoft::console::conformance
