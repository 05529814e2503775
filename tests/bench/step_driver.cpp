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
#include "shared/reference.hpp"
#include "shared/sim_plant.hpp"
#include "app/metrics/tracking_metrics.hpp"
#include "app/model/model_section.hpp"
#include "host/rig/rig_reference.hpp"
#include "support/rig_capacities.hpp"
#include "support/shipped_rigs.hpp"

namespace {

using namespace nlsoft;

// run()'s answer for a model whose shape the capacity has no kernel for.
constexpr int kOtherShape = 3;

// The rig's own task (its file's [reference]) on its simulated plant, with
// its controller defaults.
template <class Cap>
int run(const host::Rig& rig, DerivMode mode, int steps, const char* model_path) {
  if (Cap::m != rig.m() || Cap::n != rig.n() || Cap::w != rig.w()) return kOtherShape;
  const std::string path = model_path ? std::string(model_path) : std::string(NLSOFT_SOURCE_MODELS_DIR) + "/" + rig.model.file;
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  static float storage[Cap::weights + 2 * Dims<Cap>::p + 2 * Cap::n];
  static Model<Cap> M;
  // A trained model carries its fit after it, a section the firmware never reads.
  const Status parsed =
      parse_model(file.data(), model::split_model_file(file).model_size, M, storage, sizeof storage / sizeof(float));
  if (parsed == Status::TooLarge) return kOtherShape;  // the other hasel capacity may hold it
  if (parsed != Status::Ok) {
    std::fprintf(stderr, "cannot load %s\n", path.c_str());
    return 2;
  }
  Params<Cap> P = test::shipped_params<Cap>(rig.name);
  P.mode = mode;
  SimPlant plant;
  if (rig.plant.kind == nullptr || !plant.select(rig.plant.kind->kind, 1)) return 2;
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
  const RefParams r = host::rig_reference(rig, rig.reference.kind);
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
    std::fprintf(stderr, "usage: %s RIG exact|fd STEPS [MODEL_FILE]  (RIG: a rig of rigs/ with a hand-written plant)\n",
                 argv[0]);
    return 2;
  }
  const host::Rig& rig = test::shipped_rig_file(argv[1]);
  const DerivMode mode = std::strcmp(argv[2], "fd") == 0 ? DerivMode::Fd : DerivMode::Exact;
  const int steps = std::atoi(argv[3]);
  const char* model_path = argc == 5 ? argv[4] : nullptr;
  // The capacity an image of the rig is generated with: the one of the
  // rig's dimensions whose shape the model has (hasel: ours, or the
  // authors' 36-10-5-3).
  int rc = run<MsdCapacity>(rig, mode, steps, model_path);
  if (rc == kOtherShape) rc = run<HaselCapacity>(rig, mode, steps, model_path);
  if (rc == kOtherShape) rc = run<HaselAuthorsCapacity>(rig, mode, steps, model_path);
  if (rc == kOtherShape) rc = run<TendonCapacity>(rig, mode, steps, model_path);
  if (rc == kOtherShape) std::fprintf(stderr, "no image capacity of rig %s compiles this model's shape\n", argv[1]);
  return rc == 0 ? 0 : 2;
}
