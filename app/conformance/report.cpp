#include "app/conformance/report.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

namespace nlsoft::console::conformance {

int Summary::passed() const {
  int n = 0;
  for (const CheckResult& c : checks) n += c.pass ? 1 : 0;
  return n;
}

int Summary::failed() const { return int(checks.size()) - passed(); }

std::string result_line(const CheckResult& r) {
  return fmt::format("{} {}: {}", r.pass ? "PASS" : "FAIL", r.name, r.detail);
}

std::string text_summary(const Summary& s) {
  std::string out;
  if (!s.link_error.empty()) out += "link error: " + s.link_error + "\n";
  out += fmt::format("{} passed, {} failed\n", s.passed(), s.failed());
  return out;
}

std::string json_report(const Summary& s) {
  // Ordered, so the object reads in the order a person expects.
  nlohmann::ordered_json j;
  j["target"] = s.target;
  j["port"] = s.port;
  auto& checks = j["checks"] = nlohmann::ordered_json::array();
  for (const CheckResult& c : s.checks)
    checks.push_back({{"group", c.group}, {"name", c.name}, {"pass", c.pass}, {"detail", c.detail}});
  j["passed"] = s.passed();
  j["failed"] = s.failed();
  j["link_error"] = s.link_error.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(s.link_error);
  // Details may quote bytes from the firmware; never fail on them.
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace nlsoft::console::conformance
