#pragma once
// The model in force and the controller configured with it. It is read
// where its file lies (parse_model in place): the built-in one in flash, an
// uploaded one in the transfer buffer. So each model transfer, which
// overwrites that buffer, first puts the built-in model back in force (or
// none, in an image without one); and a model transfer is refused during a
// run.
#include <cstddef>
#include <cstdint>

#include "protocol/status.hpp"
#include "shared/controller.hpp"
#include "shared/model_file.hpp"
#include "shared/params.hpp"
#include "shared/rig_config.hpp"

namespace nlsoft::fw {

namespace proto = nlsoft::protocol;

template <class Cap>
class ModelSlot {
 public:
  // `staging` is the transfer buffer an uploaded model is read from.
  ModelSlot(const RigConfig& rig, const Params<Cap>& params, const uint8_t* staging, size_t staging_cap)
      : rig_(rig), params_(params), staging_(staging), staging_cap_(staging_cap) {}

  // The image's own model file (flash), kept to come back to.
  Status begin(const uint8_t* file, size_t len) {
    const Status s = load(file, len);
    if (s != Status::Ok) return s;
    builtin_ = file;
    builtin_len_ = len;
    return Status::Ok;
  }

  bool has() const { return has_; }
  uint32_t hash() const { return has_ ? model_.hash : 0; }
  Controller<Cap>& controller() { return ctl_; }
  // After a parameter changed: the controller takes it with the same model.
  void reconfigure() {
    if (has_) ctl_.configure(&model_, params_);
  }

  // Whether the model in force lies in the transfer buffer (an upload).
  bool in_staging() const {
    return has_ && model_.params != nullptr && reinterpret_cast<const uint8_t*>(model_.params) >= staging_ &&
           reinterpret_cast<const uint8_t*>(model_.params) < staging_ + staging_cap_;
  }
  // Before a model transfer writes over the buffer of the model in force.
  void restore_builtin() {
    if (!in_staging()) return;
    has_ = false;
    if (builtin_ && load(builtin_, builtin_len_) == Status::Ok) return;
    model_ = Model<Cap>{};
  }
  // A complete, CRC-checked upload of `len` bytes at `f` (the staging buffer).
  proto::StatusCode commit(const uint8_t* f, size_t len) {
    Model<Cap> probe;
    namespace at = model_offset;
    if (len < kModelHeaderSize || f[at::kM] != rig_.m || f[at::kN] != rig_.n || f[at::kW] != rig_.w)
      return proto::StatusCode::Inconsistent;
    const Status s = parse_model(f, len, probe, nullptr, 0);
    if (s != Status::Ok) return proto::StatusCode(uint8_t(s));
    const Status a = adopt(probe);
    return a == Status::Ok ? proto::StatusCode::Ok
                           : (a == Status::Unsupported ? proto::StatusCode::Unsupported : proto::StatusCode::Inconsistent);
  }

 private:
  Status load(const uint8_t* file, size_t len) {
    Model<Cap> M;
    const Status s = parse_model(file, len, M, nullptr, 0);
    if (s != Status::Ok) return s;
    return adopt(M);
  }
  Status adopt(const Model<Cap>& M) {
    if (M.m != rig_.m || M.n != rig_.n || M.w != rig_.w) return Status::Inconsistent;
    const Model<Cap> previous = model_;
    model_ = M;
    const Status s = ctl_.configure(&model_, params_);
    if (s != Status::Ok) {
      model_ = previous;  // the controller still runs the previous model
      return s;
    }
    has_ = true;
    return Status::Ok;
  }

  const RigConfig& rig_;
  const Params<Cap>& params_;
  const uint8_t* staging_;
  size_t staging_cap_;
  Model<Cap> model_{};
  bool has_ = false;
  const uint8_t* builtin_ = nullptr;  // the image's own model file, or none
  size_t builtin_len_ = 0;
  Controller<Cap> ctl_{};
};

}  // namespace nlsoft::fw
