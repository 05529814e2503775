#pragma once
// The conformance suite's frame: the results, what the checks learn about
// the firmware on the way (INFO, the parameter list) and what they must put
// back. The checks live in checks_*.cpp, one file per part of PROTOCOL.md.
#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "app/conformance/probe.hpp"

namespace nlsoft::console::conformance {

struct CheckResult {
  std::string group;  // the part of the protocol, e.g. "framing"
  std::string name;
  bool pass = false;
  std::string detail;
};

class Suite {
 public:
  using Listener = std::function<void(const CheckResult&)>;
  Suite(Probe& probe, Listener on_result) : pr(probe), on_result_(std::move(on_result)) {}

  // Every group in order; parameters it changed are set back even when the
  // link fails (LinkError propagates after that).
  void run(std::chrono::seconds patience);
  const std::vector<CheckResult>& results() const { return results_; }
  // Told of a link error as it happens, before the seconds spent asking
  // whether the device answers again (RUN_STOP, then the parameters).
  void on_link_error(std::function<void(const std::string&)> f) { on_link_error_ = std::move(f); }

  // ---- for the check files
  void check(const std::string& name, bool pass, const std::string& detail);
  void group(const std::string& g) { group_ = g; }
  // Whether the firmware offers a capability its group checks. When it does
  // not, one check named `check_name` records it: a pass for a firmware older
  // than 1.`since_minor` (saying `nothing_to_check`), a failure for one that
  // claims that version without it.
  bool offers(uint32_t capability, const char* cap_name, int since_minor, const std::string& check_name,
              const char* nothing_to_check);
  // A service this image leaves out (PROTOCOL.md 9.12, the rig file's
  // [firmware] features): its capability bit is clear, and `reply`, the
  // answer to its request, must be NACK unsupported naming `field`. One
  // check named `check_name`: left out, not failed.
  void left_out(const std::string& check_name, const char* service, const Frame& reply, uint8_t field);
  uint32_t random() { return uint32_t(rng_()); }
  std::optional<p::Status> status();
  std::optional<p::InfoEx> info_now();
  std::optional<p::ParamValue> get(uint16_t id);
  const p::ParamDesc* param(const char* name) const;
  // Sets a parameter the suite will set back; nullopt with `why` on refusal.
  std::optional<p::ParamValue> set(const p::ParamDesc& d, const std::vector<uint32_t>& words, std::string& why);
  void restore_params();

  Probe& pr;
  p::InfoEx info;
  // The firmware's sensor chips as DEVICE_GET counted them (protocol 1.4); -1: not asked.
  int devices = -1;
  std::vector<p::ParamDesc> descs;
  std::map<uint16_t, p::ParamValue> original;
  std::set<uint16_t> touched;
  uint8_t telemetry_mask = p::telemetry_field::kAll;

 private:
  Listener on_result_;
  std::function<void(const std::string&)> on_link_error_;
  std::vector<CheckResult> results_;
  std::string group_;
  std::mt19937 rng_{std::random_device{}()};
};

// The groups (checks_*.cpp).
void check_handshake(Suite& s, std::chrono::seconds patience);
void check_basics(Suite& s);
void check_params(Suite& s);
void check_references(Suite& s);
void check_framing(Suite& s);
void check_run_control(Suite& s);
void check_telemetry_rate(Suite& s);
void check_watchdog(Suite& s);
void check_transfers(Suite& s);
void check_rig(Suite& s);
void check_ident(Suite& s);
void check_devices(Suite& s);
void check_settings(Suite& s);
void check_sensor_stream(Suite& s);

// Helpers shared by the check files.
std::string join(const std::vector<std::string>& v, const char* sep);
float word_f32(uint32_t w);
uint32_t f32_word(float x);
std::string words_text(const uint32_t* v, uint8_t count, uint8_t type);
// A STATUS as a failed check quotes it: run state, watchdog bits, step.
std::string state_of(const std::optional<p::Status>& st);
bool in_state(const std::optional<p::Status>& st, p::RunState state);

}  // namespace nlsoft::console::conformance
