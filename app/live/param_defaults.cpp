#include "app/live/param_defaults.hpp"

#include "host/rig/rig_params.hpp"
#include "shared/capacity.hpp"
#include "shared/firmware_settings.hpp"
#include "shared/params.hpp"

namespace nlsoft::console {

using host::Rig;
using host::rig_params;

std::map<uint16_t, std::vector<double>> firmware_defaults(const Rig& rig) {
  std::map<uint16_t, std::vector<double>> out;
  Params<HostCapacity> P;
  if (rig_params(rig, P) != Status::Ok) return out;
  for (uint16_t id = 0; id < uint16_t(ParamId::Count); ++id) {
    float v[HostCapacity::m > HostCapacity::n ? HostCapacity::m : HostCapacity::n];
    const int count = get_param(P, ParamId(id), rig.m(), rig.n(), v);
    if (count > 0) out[id].assign(v, v + count);
  }
  const FwSettings fw{};
  out[uint16_t(FwParamId::WatchdogMs)] = {double(fw.watchdog_ms)};
  out[uint16_t(FwParamId::SafeState)] = {double(fw.safe_state)};
  return out;
}

}  // namespace nlsoft::console
