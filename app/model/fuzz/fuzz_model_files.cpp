// libFuzzer target for the model files a user hands the console: a
// controller's model (`.nlsm`: model upload, simulate, runs replay --model)
// and a plant model (`.nlsp`: runs replay --plant). Each decoder must accept
// the bytes or refuse them with a PipelineError, never crash, hang or
// throw anything else; an accepted plant model must step (every part's
// forward pass over its history) and write itself again in a form that reads
// back. Built with clang under ASan+UBSan (NLSOFT_FUZZ=ON); CI runs it
// briefly in `cmake/dev sanitize`, seeded with the shipped models and a
// plant made of them (run_fuzz.sh):
//   build-fuzz/app/model/fuzz/nlsoft-fuzz-model-files -make_seeds=seeds
//   app/model/fuzz/run_fuzz.sh build-fuzz 60
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "app/model/error.hpp"
#include "app/model/model_store.hpp"
#include "app/model/plant_model.hpp"

namespace m = nlsoft::model;

namespace {

// Plant models made of the shipped ones (MODELS: app/models): msd's as the
// one part of a one-channel plant, and the same part twice over two
// channels of a plant with one sensor.
void make_seeds(const std::string& dir, const std::string& models) {
  const m::ModelFile msd = m::load_model_file(models + "/msd.nlsm");
  m::PlantModel one;
  one.rig = "msd";
  one.m = 1, one.n = 1, one.w = 0;
  one.rate_hz = 1000;
  one.fit = "free run: x RMSE 0.001 m";
  one.parts.push_back({{0}, msd});
  m::PlantModel two = one;
  two.w = 1;
  two.parts.push_back({{1}, msd});
  int i = 0;
  for (m::PlantModel* pm : {&one, &two}) {
    const std::vector<uint8_t> b = m::encode_plant_model(*pm);
    std::ofstream(dir + "/plant" + std::to_string(i++) + ".nlsp", std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  const char* models = std::getenv("NLSOFT_MODELS");
  for (int i = 1; i < *argc; ++i)
    if (std::strncmp((*argv)[i], "-make_seeds=", 12) == 0) {
      if (!models) std::fprintf(stderr, "-make_seeds: set NLSOFT_MODELS to app/models\n"), std::exit(2);
      make_seeds((*argv)[i] + 12, models);
      std::exit(0);
    }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  try {
    m::decode_model(bytes, "fuzz.nlsm");
  } catch (const m::PipelineError&) {
  }
  m::PlantModel pm;
  try {
    pm = m::decode_plant_model(bytes, "fuzz.nlsp");
  } catch (const m::PipelineError&) {
    return 0;
  }
  m::PlantSimulator sim(pm);
  std::vector<float> start(size_t(pm.channels()), 0.5f), u(size_t(pm.m), 0.25f);
  sim.rest_at(start.data(), u.data());
  for (int k = 0; k < 3; ++k) sim.step(u.data());
  const std::vector<uint8_t> again = m::encode_plant_model(pm);
  const m::PlantModel back = m::decode_plant_model(again, "again.nlsp");
  if (back.parts.size() != pm.parts.size() || back.rig != pm.rig) std::abort();
  return 0;
}
