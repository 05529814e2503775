#pragma once
// How the suite's results are shown: a line per check as it completes, then
// `N passed, M failed`; or one JSON object for machines.
#include <cstdio>
#include <string>
#include <vector>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

struct Summary {
  std::string target;  // port, or "sim hasel", "qemu msd"
  std::string port;
  std::vector<CheckResult> checks;
  std::string link_error;  // empty: none
  int passed() const;
  int failed() const;
};

// `PASS|FAIL name: detail`.
std::string result_line(const CheckResult& r);
// The closing lines of the text report.
std::string text_summary(const Summary& s);
// {"target", "port", "checks":[{"group","name","pass","detail"}...], "passed", "failed", "link_error"}.
std::string json_report(const Summary& s);

}  // namespace nlsoft::console::conformance
