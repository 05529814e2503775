#pragma once
// Whether a sample frame (TELEMETRY, IDENT_SAMPLE) can be taken, decided at
// the one place the session accepts it, so that nothing after it (samples,
// recorder, plots, metrics) can see an impossible value: its dimensions must
// be the firmware's INFO (a frame of another shape would be read past the
// vectors it fills), and every value it carries must be finite (a NaN scores
// as a perfect run). A refused frame is counted lost, never scored.
#include <string>

#include "protocol/messages.hpp"

namespace nlsoft::console {

// Why the frame is refused, in words ("dimensions m=0 n=58 w=0, the
// firmware's INFO says m=6 n=3 w=18"); empty when it is taken. info: the
// firmware's INFO, or null before the handshake (then only what the
// console's sample can hold is checked).
std::string telemetry_refusal(const protocol::Telemetry& t, const protocol::Info* info);
std::string ident_sample_refusal(const protocol::IdentSample& s, const protocol::Info* info);
// Protocol 1.6: its w must be INFO's (a sample keeps at most that many).
std::string sensor_sample_refusal(const protocol::SensorSample& s, const protocol::Info* info);

// What is wrong with a frame: its shape, or its values.
enum class SampleFault { None, Dimensions, NotFinite };
SampleFault telemetry_fault(const protocol::Telemetry& t, const protocol::Info* info);
SampleFault ident_sample_fault(const protocol::IdentSample& s, const protocol::Info* info);
SampleFault sensor_sample_fault(const protocol::SensorSample& s, const protocol::Info* info);

}  // namespace nlsoft::console
