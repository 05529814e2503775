#pragma once
// The firmware as the console uses it: handshake, parameters by name,
// references, uploads, run control. Every method is one or a few requests
// through Session; refusals come back as exceptions in words.
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/link/param_catalog.hpp"
#include "app/link/session.hpp"
#include "protocol/messages.hpp"
#include "shared/firmware_features.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

// Thrown for a refused parameter write: what() names the element and range.
struct ParamRefused : NackError {
  ParamRefused(const protocol::Nack& n, const std::string& words) : NackError(n, words) {}
};

// Empty when the firmware offers the service of shared/firmware_features.hpp
// `feature_bit`; else why not, for an error: its image was built without it
// (PROTOCOL.md 9.12), or one older than protocol 1.5 may predate it.
std::string firmware_lacks(const protocol::Info& info, uint8_t protocol_minor, uint32_t feature_bit);

// REF_SELECT of a reference: its fields as they are (the payload is RefParams).
protocol::RefSelect ref_select_of(const RefParams& ref);

class Device {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;

  explicit Device(Session& session) : session_(session) {}

  // INFO_GET, and RIG_GET when INFO_EX has the RIG capability (protocol
  // 1.2); checks protocol version and dimensions. Throws LinkError.
  protocol::Info handshake();
  protocol::Info info() const;
  // The largest object XFER_BEGIN accepts for `kind` (INFO_EX); 0 when the
  // firmware does not say (protocol 1.0).
  uint32_t transfer_limit(protocol::XferKind kind) const;
  uint8_t protocol_minor() const;
  // RIG_INFO: the rig's name and hash and the model shapes the firmware
  // accepts; none from a 1.1 or 1.0 firmware, which then goes by INFO's
  // platform number as before.
  std::optional<protocol::RigInfo> rig() const;
  // The rig's name where the console used to name the platform: RIG_INFO's,
  // else the platform's ("hasel", "custom").
  std::string rig_label() const;
  bool has(uint32_t capability) const { return (info().capabilities & capability) != 0; }
  // firmware_lacks of this firmware.
  std::string lacks(uint32_t feature_bit) const;

  // Walks PARAM_LIST 0..count-1.
  void load_params(const Progress& progress = {});
  std::shared_ptr<const ParamCatalog> catalog() const;

  std::vector<double> get(const ParamInfo& p);
  // Returns the value now in force (echoed by the firmware). Throws
  // ParamRefused on NACK, LinkError when the link fails.
  std::vector<double> set(const ParamInfo& p, const std::vector<double>& values);
  // Current value of every parameter, in list order.
  std::vector<std::pair<ParamInfo, std::vector<double>>> get_all();

  void select_reference(const RefParams& ref);
  // XFER_BEGIN/CHUNK/COMMIT of one object; resumes a matching partial
  // upload. Throws NackError/LinkError; the previous object stays in force.
  void upload(protocol::XferKind kind, const std::vector<uint8_t>& object, const Progress& progress = {});

  void run_start(uint32_t run_id);
  // Protocol 1.3: an identification run (needs the IDENT capability).
  void ident_start(const protocol::IdentStart& req);
  void run_stop();
  void run_hold(protocol::HoldMode mode);
  void telemetry_config(uint8_t mask, uint16_t decimation);
  // Protocol 1.6: a SENSOR_SAMPLE before each TELEMETRY (a firmware with
  // the SENSOR_STREAM capability: a rig with sensors).
  void sensor_stream(bool on);
  protocol::Status status();
  // Protocol 1.4: every sensor chip's state (DEVICE_GET 0..count-1); empty
  // for a firmware without chips. Throws CliError for a firmware without
  // the DEVICES capability (it cannot say).
  std::vector<protocol::DeviceStatus> devices();
  // Protocol 1.5: SETTINGS (PROTOCOL.md 9.11): save the parameters in force
  // to the firmware's flash, put the built-in ones back, or ask where the
  // settings in force came from (the firmware's LOG answers). Returns what
  // was done, in words; throws CliError for a firmware without the
  // SETTINGS capability or while a run is active, NackError otherwise.
  std::string settings(protocol::SettingsAction action);
  // Why settings() would be refused before anything is sent; "" when it would not.
  std::string settings_missing() const;

  Session& session() { return session_; }
  // Asked between the requests of a long exchange (an upload's chunks, the
  // parameter list): true ends it with a LinkError. The console's is a
  // signal (Ctrl-C, SIGTERM).
  void set_give_up(std::function<bool()> give_up) { give_up_ = std::move(give_up); }

 private:
  Session& session_;
  std::function<bool()> give_up_;
  mutable std::mutex mu_;
  protocol::InfoEx info_{};
  std::optional<protocol::RigInfo> rig_;
  std::shared_ptr<const ParamCatalog> catalog_ = std::make_shared<ParamCatalog>();
};

}  // namespace nlsoft::console
