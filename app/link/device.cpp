#include "app/link/device.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

#include "host/files/cli_error.hpp"
#include "app/link/info_check.hpp"
#include "app/link/protocol_version.hpp"
#include "host/files/printable.hpp"
#include "app/link/session_words.hpp"
#include "protocol/crc.hpp"

namespace nlsoft::console {

using host::CliError;
using host::printable;
using host::printable_into;

namespace p = nlsoft::protocol;

p::Info Device::handshake() {
  p::InfoEx ex = session_.call<p::InfoEx>(p::InfoGet{});
  const p::Info& info = ex.info;
  // The firmware's name is escaped where it is decoded: nothing after this
  // (a terminal, a parameter file, the database) sees it raw.
  printable_into(ex.info.firmware, ex.info.firmware, sizeof ex.info.firmware);
  if (info.protocol_version != p::kProtocolVersion)
    throw LinkError(fmt::format("the firmware speaks protocol v{}, this console {}", info.protocol_version,
                                protocol_version_text()));
  if (const std::string why = info_refusal(info); !why.empty()) throw LinkError(why + ": not used");
  // A firmware that advertises RIG answers RIG_GET; one that does not is
  // never asked (a 1.1 firmware would drop the frame and cost us a timeout).
  std::optional<p::RigInfo> rig;
  if (info.capabilities & p::capability::kRig) rig = session_.call<p::RigInfo>(p::RigGet{});
  if (rig) printable_into(rig->rig_name, rig->rig_name, sizeof rig->rig_name);
  {
    std::lock_guard<std::mutex> lock(mu_);
    info_ = ex;
    rig_ = rig;
  }
  session_.set_nominal_rate(info.loop_rate_hz);
  return info;
}

std::optional<p::RigInfo> Device::rig() const {
  std::lock_guard<std::mutex> lock(mu_);
  return rig_;
}

std::string Device::rig_label() const {
  std::lock_guard<std::mutex> lock(mu_);
  if (rig_ && rig_->rig_name[0] != '\0') return rig_->rig_name;  // escaped in handshake()
  return platform_words(info_.info.platform);
}

p::Info Device::info() const {
  std::lock_guard<std::mutex> lock(mu_);
  return info_.info;
}

uint32_t Device::transfer_limit(p::XferKind kind) const {
  std::lock_guard<std::mutex> lock(mu_);
  return kind == p::XferKind::Model ? info_.model_max : kind == p::XferKind::RefTable ? info_.table_max : 0;
}

uint8_t Device::protocol_minor() const {
  std::lock_guard<std::mutex> lock(mu_);
  return info_.protocol_minor;
}

void Device::load_params(const Progress& progress) {
  std::vector<ParamInfo> list;
  p::ParamList req;
  uint16_t count = 1;
  for (uint16_t i = 0; i < count; ++i) {
    if (give_up_ && give_up_()) throw LinkError(fmt::format("interrupted reading parameter {} of {}", i, count));
    req.index = i;
    const p::ParamDesc d = session_.call<p::ParamDesc>(req);
    if (i == 0) count = d.count;
    if (d.index != i) throw LinkError(fmt::format("PARAM_LIST({}) answered with index {}", i, d.index));
    if (d.size == 0 || d.size > p::kMaxParamValues)
      throw LinkError(fmt::format("parameter '{}' has an impossible size {}", printable(d.name), d.size));
    list.push_back(param_info_from(d));
    if (progress) progress(size_t(i) + 1, count);
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    apply_capacity(list, info_.info.max_n, info_.info.max_nc);
  }
  auto cat = std::make_shared<const ParamCatalog>(std::move(list));
  std::lock_guard<std::mutex> lock(mu_);
  catalog_ = std::move(cat);
}

std::shared_ptr<const ParamCatalog> Device::catalog() const {
  std::lock_guard<std::mutex> lock(mu_);
  return catalog_;
}

std::vector<double> Device::get(const ParamInfo& info) {
  p::ParamGet req;
  req.id = info.id;
  const p::ParamValue v = session_.call<p::ParamValue>(req);
  if (v.id != info.id) throw LinkError(fmt::format("PARAM_GET({}) answered for id {}", info.name, v.id));
  return decode_param_values(info, v.values, v.count);
}

std::vector<double> Device::set(const ParamInfo& info, const std::vector<double>& values) {
  if (values.size() != info.size || values.size() > p::kMaxParamValues)
    throw CliError(fmt::format("{} takes {} values, got {}", info.name, info.size, values.size()));
  p::ParamSet req;
  req.id = info.id;
  req.count = uint8_t(values.size());
  encode_param_values(info, values, req.values);
  try {
    const p::ParamValue v = session_.call<p::ParamValue>(req);
    return decode_param_values(info, v.values, v.count);
  } catch (const NackError& e) {
    throw ParamRefused(e.nack, describe_param_refusal(info, e.nack, values));
  }
}

std::vector<std::pair<ParamInfo, std::vector<double>>> Device::get_all() {
  std::vector<std::pair<ParamInfo, std::vector<double>>> out;
  const auto cat = catalog();
  for (const ParamInfo& pi : cat->all()) out.emplace_back(pi, get(pi));
  return out;
}

p::RefSelect ref_select_of(const RefParams& ref) {
  static_assert(sizeof(RefParams) == 52, "REF_SELECT payload is RefParams as is");
  p::RefSelect req;
  req.ref_id = uint8_t(ref.kind);
  req.level_count = ref.level_count;
  req.hold = ref.hold;
  req.a = ref.A;
  req.b = ref.B;
  req.c = ref.C;
  std::copy(ref.c, ref.c + 3, req.center);
  req.omega = ref.omega;
  req.lambda = ref.lambda;
  req.scale = ref.scale;
  std::copy(ref.levels, ref.levels + 3, req.levels);
  return req;
}

void Device::select_reference(const RefParams& ref) { session_.call<p::Ack>(ref_select_of(ref)); }

void Device::upload(p::XferKind kind, const std::vector<uint8_t>& object, const Progress& progress) {
  if (object.empty()) throw CliError("nothing to upload: the object is empty");
  p::XferBegin begin;
  begin.kind = uint8_t(kind);
  begin.total_size = uint32_t(object.size());
  begin.crc32 = p::crc32(object.data(), object.size());
  p::XferAck ack;
  try {
    ack = session_.call<p::XferAck>(begin);
  } catch (const NackError& e) {
    // NACK has no room for the limit; INFO_EX said it (protocol 1.1).
    const uint32_t limit = transfer_limit(kind);
    if (e.nack.status != uint8_t(p::StatusCode::TooLarge) || limit == 0) throw;
    throw NackError(e.nack, fmt::format("{}: {} bytes, the firmware takes at most {} bytes for this kind", e.what(),
                                        object.size(), limit));
  }
  // Bounded however the firmware answers: progress is the furthest offset
  // it has acknowledged, so offsets that go forward and back again are
  // stalls too, and no upload takes more than twice its chunks (plus
  // retries); a signal ends it between chunks.
  size_t stalls = 0;
  uint32_t furthest = ack.next_offset;
  const size_t chunks = (object.size() + p::kMaxChunkData - 1) / p::kMaxChunkData;
  const size_t max_requests = 2 * chunks + 16;
  size_t requests = 0;
  while (ack.next_offset < object.size()) {
    if (give_up_ && give_up_()) throw LinkError(fmt::format("upload interrupted at byte {} of {}", furthest, object.size()));
    if (++requests > max_requests)
      throw LinkError(fmt::format("upload abandoned after {} chunks for {} bytes: the firmware's offsets went back "
                                  "and forth (furthest {})",
                                  requests - 1, object.size(), furthest));
    if (progress) progress(ack.next_offset, object.size());
    p::XferChunk chunk;
    chunk.kind = uint8_t(kind);
    chunk.offset = ack.next_offset;
    chunk.size = uint8_t(std::min<size_t>(p::kMaxChunkData, object.size() - ack.next_offset));
    std::memcpy(chunk.data, object.data() + ack.next_offset, chunk.size);
    ack = session_.call<p::XferAck>(chunk);
    // The firmware ignores out-of-order chunks and tells us where it is;
    // a peer that never gets further would loop forever without this guard.
    stalls = ack.next_offset > furthest ? 0 : stalls + 1;
    furthest = std::max(furthest, ack.next_offset);
    if (stalls > 8) throw LinkError(fmt::format("upload stalled at byte {} of {}", ack.next_offset, object.size()));
  }
  if (progress) progress(object.size(), object.size());
  p::XferCommit commit;
  commit.kind = uint8_t(kind);
  session_.call<p::Ack>(commit);
}

void Device::run_start(uint32_t run_id) {
  p::RunStart req;
  req.run_id = run_id;
  session_.call<p::Ack>(req);
}

void Device::ident_start(const p::IdentStart& req) { session_.call<p::Ack>(req); }

void Device::run_stop() { session_.call<p::Ack>(p::RunStop{}); }

void Device::run_hold(p::HoldMode mode) {
  p::RunHold req;
  req.mode = uint8_t(mode);
  session_.call<p::Ack>(req);
}

void Device::telemetry_config(uint8_t mask, uint16_t decimation) {
  p::TelemetryConfig req;
  req.mask = mask;
  req.decimation = decimation;
  session_.call<p::Ack>(req);
}

void Device::sensor_stream(bool on) {
  p::SensorStream req;
  req.on = on ? 1 : 0;
  session_.call<p::Ack>(req);
}

p::Status Device::status() { return session_.call<p::Status>(p::StatusGet{}); }

std::string firmware_lacks(const p::Info& info, uint8_t protocol_minor, uint32_t feature_bit) {
  const FirmwareFeature* f = firmware_feature(feature_bit);
  // The service's first bit says whether it is there (IDENT; IDENT_MIXED
  // only refines it).
  const uint32_t primary = f ? f->capabilities & (0u - f->capabilities) : 0;
  if (!f || (info.capabilities & primary) != 0) return "";
  return fmt::format("the firmware ({} {}.{}.{}, protocol 1.{}) was built without {}: its rig file's [firmware] "
                     "features leave out \"{}\" (docs/rig-file.md){}",
                     info.firmware, info.fw_major, info.fw_minor, info.fw_patch, protocol_minor, f->what, f->name,
                     protocol_minor < 5 ? ", or it predates the service: update it" : "");
}

std::string Device::lacks(uint32_t feature_bit) const { return firmware_lacks(info(), protocol_minor(), feature_bit); }

std::string Device::settings_missing() const {
  if (has(p::capability::kSettings)) return "";
  return fmt::format(
      "the firmware ({}) keeps no settings: it has no SETTINGS capability (protocol 1.5; an image built without "
      "\"settings\" in its rig file's [firmware] features, an stm32f4 image under QEMU, which has no flash "
      "interface, an MPS2 image (mps2-an386, mps2-an500), or a simulator started without --settings); its "
      "parameters last until it resets",
      protocol_minor() < 5 ? fmt::format("protocol 1.{}", protocol_minor()) : std::string("this one"));
}

std::string Device::settings(p::SettingsAction action) {
  if (const std::string missing = settings_missing(); !missing.empty()) throw CliError(missing);
  p::Settings req;
  req.action = uint8_t(action);
  try {
    session_.call<p::Ack>(req);
  } catch (const NackError& e) {
    if (e.status() == p::StatusCode::WrongState)
      throw CliError("the firmware changes its saved settings only while no run is active (a flash erase would "
                     "stall its control loop): stop the run first");
    throw;
  }
  switch (action) {
    case p::SettingsAction::Save:
      return "settings saved: the firmware starts with the parameters in force from now on";
    case p::SettingsAction::Defaults:
      return "settings: the built-in parameters are in force again, and the firmware starts with them from now on";
    case p::SettingsAction::Report: break;
  }
  return "settings: the firmware says where its settings came from (its LOG)";
}

std::vector<p::DeviceStatus> Device::devices() {
  if (!has(p::capability::kDevices))
    throw CliError(fmt::format("the firmware ({}) cannot report its sensor chips: it has no DEVICES capability "
                               "(protocol 1.4)",
                               protocol_minor() < 4 ? fmt::format("protocol 1.{}", protocol_minor())
                                                    : std::string("this one")));
  std::vector<p::DeviceStatus> out;
  p::DeviceGet get;
  try {
    do {
      out.push_back(session_.call<p::DeviceStatus>(get));
      // PROTOCOL.md 7: 1..8 chips, the same count in every answer.
      const p::DeviceStatus& d = out.back();
      if (d.count == 0 || d.count > kMaxChips || d.count != out.front().count || d.index != get.index)
        throw LinkError(fmt::format("DEVICE_GET({}) answered index {} of {} chips: a firmware has 1..{} chips, "
                                    "the same count in every answer",
                                    get.index, d.index, d.count, kMaxChips));
      printable_into(out.back().name, out.back().name, sizeof out.back().name);
      get.index = uint8_t(get.index + 1);
    } while (get.index < out.front().count);
  } catch (const NackError& e) {
    // Index 0 refused: the image has no chips. A later index: the count lied.
    if (get.index != 0 || e.status() != p::StatusCode::UnknownId) throw;
  }
  return out;
}

}  // namespace nlsoft::console
