#pragma once
// Test support: the shipped rigs as the tests take them, read from their
// files in rigs/ (the one description of each rig) through the console's
// loader. Link nlsoft_test_shipped_rigs (tests/CMakeLists.txt).
#include <map>
#include <stdexcept>
#include <string>

#include "app/model/plant_target.hpp"
#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig.hpp"
#include "host/rig/rig_params.hpp"
#include "app/rig/rig_pipeline.hpp"

namespace nlsoft::test {

// rigs/<name>.toml, loaded once per process: a RigConfig points at its name.
inline const host::Rig& shipped_rig_file(const std::string& name) {
  static std::map<std::string, host::Rig> loaded;
  auto it = loaded.find(name);
  if (it == loaded.end())
    it = loaded.emplace(name, host::load_rig(std::string(NLSOFT_RIGS_DIR) + "/" + name + ".toml")).first;
  return it->second;
}

// The rig as the firmware holds it (what the simulator serves).
inline RigConfig shipped_config(const std::string& name) { return host::firmware_rig(shipped_rig_file(name)); }

// The rig's controller defaults in a capacity; throws (a failed test) when it cannot hold them.
template <class Cap>
Params<Cap> shipped_params(const std::string& name) {
  Params<Cap> P;
  if (host::rig_params(shipped_rig_file(name), P) != Status::Ok)
    throw std::runtime_error("the capacity cannot hold rig " + name + "'s controller");
  return P;
}

// The rig as `dataset` and `train` take it.
inline model::PlantTarget shipped_target(const std::string& name) {
  return console::rig_plant_target(shipped_rig_file(name));
}

}  // namespace nlsoft::test
