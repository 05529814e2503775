#pragma once
// What INFO (or INFO_EX) may say for the console to take the firmware at
// its word: every count the console sizes a buffer or a wait by is checked
// here, once, where INFO is accepted (Device::handshake), so no later code
// divides by a loop rate of 0 or sizes a sample by 58 outputs.
#include <string>

#include "protocol/messages.hpp"

namespace nlsoft::console {

// The largest loop rate a rig file may give (host/rig/rig_loader.cpp:
// rate_hz <= 1e5); a firmware claiming more is not a rig the console knows.
constexpr uint32_t kMaxLoopRateHz = 100000;

// DEVICE_STATUS count: a firmware has 1..8 sensor chips (PROTOCOL.md 7).
constexpr uint8_t kMaxChips = 8;

// Why the console refuses this INFO, in words ("the firmware reports a loop
// rate of 0 Hz"); empty when it is plausible.
std::string info_refusal(const protocol::Info& info);

}  // namespace nlsoft::console
