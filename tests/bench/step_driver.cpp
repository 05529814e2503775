// Runs K control steps of a platform's shipped model on its paper task with
// the simulated plant, with the firmware's capacity (the MCU code path), for
// instruction counting under valgrind (see instructions-per-step). Prints the
// mean Newton iterations and the tracking nRMSE of the true plant output
// (app/metrics/tracking_metrics.hpp) over the K steps. Usage: nlsoft-step-driver PLATFORM exact|fd K [MODEL]
// MODEL: a model file of the platform's dimensions (default: the shipped one),
// e.g. one imported from Keras with `nlsoft-console model import`.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "shared/controller.hpp"
#include "shared/model_file.hpp"
#include "shared/platform.hpp"
#include "shared/plant_hasel.hpp"
#include "shared/plant_tendon.hpp"
#include "shared/reference.hpp"
#include "shared/sim_plant.hpp"
#include "app/metrics/tracking_metrics.hpp"

namespace {

using namespace nlsoft;

// run()'s answer for a model whose shape the capacity has no kernel for.
constexpr int kOtherShape = 3;

template <class Cap>
int run(PlatformId id, DerivMode mode, int steps, const char* model) {
  const std::string path =
      model ? std::string(model) : std::string(NLSOFT_SOURCE_MODELS_DIR) + "/" + platform_name(id) + ".nlsm";
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  static float storage[Cap::weights + 2 * Dims<Cap>::p + 2 * Cap::n];
  static Model<Cap> M;
  const Status parsed = parse_model(file.data(), file.size(), M, storage, sizeof storage / sizeof(float));
  if (parsed == Status::TooLarge) return kOtherShape;  // the other hasel capacity may hold it
  if (parsed != Status::Ok) {
    std::fprintf(stderr, "cannot load %s\n", path.c_str());
    return 2;
  }
  Params<Cap> P;
  preset_params(preset(id), P);
  P.mode = mode;
  SimPlant plant;
  if (!plant.select(find_plant(platform_name(id))->kind, 1)) return 2;
  plant.input_limits(P.u_min, P.u_max);
  float u[Cap::m], l[Cap::w + 1] = {}, y[Cap::n];
  plant.neutral_input(u);
  for (int k = 0; k < 200; ++k) plant.step(u, plant.dt());
  plant.sensors(l);
  plant.output(y);
  static Controller<Cap> ctl;
  const Status configured = ctl.configure(&M, P);
  if (configured == Status::Unsupported) return kOtherShape;
  if (configured != Status::Ok) return 2;
  if (P.feedback == Feedback::Measured)
    ctl.reset(u, y, l);
  else
    ctl.reset_at_rest(u, l);
  RefParams r{};
  r.hold = 10;
  r.scale = 1.0f;
  if (id == PlatformId::Hasel) {
    r.kind = RefKind::Swirl;
    for (int i = 0; i < 3; ++i) r.c[i] = HaselPlant::kSwirlCentre[i];
  } else if (id == PlatformId::Tendon) {
    r.kind = RefKind::Infinity;
    r.A = TendonPlant::kInfinity[0], r.B = TendonPlant::kInfinity[1], r.C = TendonPlant::kInfinity[2];
    r.omega = 2.0f * 3.14159265f / 960.0f;
  } else {
    r.kind = RefKind::Step;
    r.level_count = 1;
    r.levels[0] = 0.5f;
    r.hold = 60000;
  }
  long iterations = 0;
  std::vector<float> y_ref, y_true;
  for (int k = 0; k < steps; ++k) {
    float ref[Cap::N * Cap::n];
    for (int j = 0; j < P.N; ++j) reference_at(r, nullptr, uint32_t(k + 1 + j), ref + j * M.n, M.n);
    const StepResult<Cap> s = ctl.step(ref, l, y);
    iterations += s.iterations;
    plant.step(s.u, plant.dt());
    plant.sensors(l);
    plant.output(y);
    y_ref.insert(y_ref.end(), ref, ref + M.n);
    y_true.insert(y_true.end(), y, y + M.n);
  }
  const double nrmse = steps ? console::tracking_metrics(y_ref, y_true, M.n, P.Q).nrmse : 0.0;
  std::printf("%.3f %.5f\n", steps ? double(iterations) / steps : 0.0, nrmse);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: %s msd|hasel|tendon exact|fd STEPS [MODEL_FILE]\n", argv[0]);
    return 2;
  }
  PlatformId id;
  if (!platform_from_name(argv[1], &id)) return 2;
  const DerivMode mode = std::strcmp(argv[2], "fd") == 0 ? DerivMode::Fd : DerivMode::Exact;
  const int steps = std::atoi(argv[3]);
  const char* model = argc == 5 ? argv[4] : nullptr;
  switch (id) {
    case PlatformId::Msd: return run<MsdCapacity>(id, mode, steps, model) == 0 ? 0 : 2;
    case PlatformId::Hasel: {
      // each hasel image compiles one shape: ours, or the authors' 36-10-5-3
      int rc = run<HaselCapacity>(id, mode, steps, model);
      if (rc == kOtherShape) rc = run<HaselAuthorsCapacity>(id, mode, steps, model);
      if (rc == kOtherShape) std::fprintf(stderr, "no hasel image compiles the shape of this model\n");
      return rc == 0 ? 0 : 2;
    }
    case PlatformId::Tendon: return run<TendonCapacity>(id, mode, steps, model) == 0 ? 0 : 2;
    default: break;
  }
  return 2;
}
