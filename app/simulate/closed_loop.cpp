#include "app/simulate/closed_loop.hpp"

#include <fmt/format.h>

#include <chrono>
#include <memory>

#include "host/files/cli_error.hpp"
#include "shared/controller.hpp"
#include "shared/pid.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

using Cap = HostCapacity;

std::string plant_name(const LoopSetup& s) {
  const PlantEntry* e = plant_entry(s.plant);
  return !s.plant_name.empty() ? s.plant_name : e != nullptr ? e->name : "?";
}

// The loop's plant: the simulated one, or one standing in for it.
class LoopPlant {
 public:
  explicit LoopPlant(const LoopSetup& s) : s_(s) {
    if (s.stand_in) {
      m_ = s.stand_in->m, n_ = s.stand_in->n, w_ = s.stand_in->w;
      dt_ = s.stand_in->dt;
      return;
    }
    if (s.generic == nullptr) {
      if (!sim_.select(s.plant, s.seed))
        throw CliError(fmt::format("plant kind {} is no hand-written plant (the generic plant needs its rig's spec)",
                                   int(s.plant)));
    } else if (!sim_.select(*s.generic, s.seed)) {
      throw CliError(fmt::format("the generic plant of '{}' cannot run: {}", plant_name(s),
                                 generic_spec_problem(*s.generic)));
    }
    m_ = sim_.m(), n_ = sim_.n(), w_ = sim_.w();
    dt_ = sim_.dt();
  }
  int m() const { return m_; }
  int n() const { return n_; }
  int w() const { return w_; }
  float dt() const { return dt_; }
  // At rest: the settling steps at neutral, or the plant model at its start.
  void settle(float* u) {
    if (s_.stand_in) return s_.stand_in->rest(u);
    sim_.neutral_input(u);
    for (long k = 0; k < s_.settle_steps; ++k) sim_.step(u, dt_);
  }
  void step(const float* u) { s_.stand_in ? s_.stand_in->step(u) : sim_.step(u, dt_); }
  void read(float* y, float* l) {
    if (s_.stand_in) return s_.stand_in->read(y, l);
    sim_.output(y);
    sim_.sensors(l);
  }

 private:
  const LoopSetup& s_;
  SimPlant sim_;
  int m_ = 0, n_ = 0, w_ = 0;
  float dt_ = 0;
};

void check_model_fits(const LoopSetup& s, const LoopPlant& plant) {
  if (!s.model) throw CliError("the MPC controller needs a model (--model FILE)");
  const Model<Cap>& M = *s.model;
  if (M.m != plant.m() || M.n != plant.n() || M.w != plant.w())
    throw CliError(fmt::format("model dimensions m={} n={} w={} do not match rig '{}' (m={} n={} w={})", M.m,
                               M.n, M.w, plant_name(s), plant.m(), plant.n(), plant.w()));
}

}  // namespace

Trace run_closed_loop(const LoopSetup& s, const Progress& progress) {
  LoopPlant plant(s);
  const int m = plant.m(), n = plant.n();
  const float dt = plant.dt();
  if (s.controller == ControllerKind::Mpc) check_model_fits(s, plant);
  if (s.controller == ControllerKind::Pid && (m != n || n > kPidMaxAxes))
    throw CliError(fmt::format("the PID baseline runs one loop per axis, output i on input i; '{}' has m={} n={}",
                               plant_name(s), m, n));
  if (const char* why = reference_check(s.reference)) throw CliError(fmt::format("reference refused: {}", why));

  float u[Cap::m] = {}, y[Cap::n] = {}, l[Cap::w] = {};
  plant.settle(u);
  plant.read(y, l);

  auto ctl = std::make_unique<Controller<Cap>>();  // large scratch: keep it off the stack
  Pid pid;
  if (s.controller == ControllerKind::Mpc) {
    if (ctl->configure(s.model, s.params) != Status::Ok)
      throw CliError("the parameter set is inconsistent with this model");
    // The controller sees the plant's output only when an observer exists
    // (feedback = measured); otherwise it starts from its model's rest point,
    // as the firmware does.
    if (s.params.feedback == Feedback::Measured)
      ctl->reset(u, y, l);
    else
      ctl->reset_at_rest(u, l);
  } else {
    if (!pid.configure(n, s.pid, s.params.u_min, s.params.u_max, s.pid_output_scale, s.pid_d_filter_tau))
      throw CliError(fmt::format("the PID baseline of '{}' cannot run: its gains, scale or the input limits are "
                                 "not usable",
                                 plant_name(s)));
  }

  Trace t;
  t.m = m, t.n = n, t.dt = dt;
  const size_t rows = size_t(s.steps);
  t.y_ref.reserve(rows * n), t.y_hat.reserve(rows * n), t.y_true.reserve(rows * n), t.u.reserve(rows * m);
  t.cost.reserve(rows), t.iterations.reserve(rows), t.flags.reserve(rows), t.solve_us.reserve(rows);

  const int N = s.controller == ControllerKind::Mpc ? s.params.N : 1;
  std::vector<float> ref(size_t(N) * n);
  for (int j = 0; j < N; ++j)
    for (int i = kRefMaxDim; i < n; ++i) ref[size_t(j * n + i)] = s.ref_hold[i];
  const long report_every = s.steps / 200 + 1;
  for (long k = 0; k < s.steps; ++k) {
    for (int j = 0; j < N; ++j) reference_at(s.reference, nullptr, uint32_t(k + 1 + j), &ref[size_t(j) * n], n);
    float y_hat[Cap::n] = {};
    const auto t0 = std::chrono::steady_clock::now();
    if (s.controller == ControllerKind::Mpc) {
      const StepResult<Cap> r = ctl->step(ref.data(), l, y);
      for (int i = 0; i < m; ++i) u[i] = r.u[i];
      for (int i = 0; i < n; ++i) y_hat[i] = r.y_hat[i];
      t.cost.push_back(r.cost);
      t.iterations.push_back(r.iterations);
      t.flags.push_back(r.flags);
    } else {
      pid.step(ref.data(), y, dt, u);
      for (int i = 0; i < n; ++i) y_hat[i] = ref[i];
      t.cost.push_back(0.0f);
      t.iterations.push_back(0);
      t.flags.push_back(0);
    }
    const auto t1 = std::chrono::steady_clock::now();
    t.solve_us.push_back(std::chrono::duration<float, std::micro>(t1 - t0).count());

    plant.step(u);
    plant.read(y, l);
    t.y_ref.insert(t.y_ref.end(), ref.begin(), ref.begin() + n);
    t.y_hat.insert(t.y_hat.end(), y_hat, y_hat + n);
    t.y_true.insert(t.y_true.end(), y, y + n);
    t.u.insert(t.u.end(), u, u + m);
    if (progress && (k % report_every == 0 || k + 1 == s.steps)) progress(k + 1, s.steps);
  }
  return t;
}

}  // namespace nlsoft::console
