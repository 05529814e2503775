#pragma once
// A plant model: what stands in for a real rig when one of its recorded runs
// is replayed through a changed controller (`runs replay N --plant FILE`).
// It is trained from the rig's recorded runs (`train --plant`) and kept
// apart from the controller's model: the controller's model predicts the
// outputs y from the sensors l, so a stand-in must predict l as well, n + w
// channels in all (hasel: 3 + 18). A model file holds at most
// HostCapacity::n outputs, so the plant is a few ordinary models ("parts"),
// each predicting up to that many channels from their own history and the
// inputs' alone (no sensors: w = 0), each trained for its own free run.
// Parts that read each other's channels as sensors were tried first: each
// was trained on the others' measured values, and stepped together they fed
// their errors around (hasel, 10 min of aprbs and a Swirl: the held-out
// free run 9.8-25.6 % of each output's span, against 1.6-2.0 % for parts
// that read only the inputs).
//
// File (".nlsp"), little-endian:
//
//   off  size  field
//   0    4     magic "NLSP"
//   4    1     format version (1)
//   5    1     m, 6: n, 7: w (the rig's dimensions)
//   8    1     parts P (1..kMaxPlantParts)
//   9    3     reserved, zero
//   12   4     the rig's control rate, Hz (float)
//   16   2     length R of the rig's name (1..kMaxPlantText)
//   18   2     length F of the fit's text (0..kMaxPlantText)
//   20   R     the rig's name
//   20+R F     the fit, in words (the free run of held-out rows, as train printed it)
//   then, per part:
//     1    c: channels it predicts (1..HostCapacity::n)
//     c    the channels, each < n + w (c < n: y_c, else l_{c-n}), each in one part only
//     4    length L of its model (a model file without sections, shared/model_file.hpp)
//     L    the model: m inputs, c outputs, no sensors
//   end  4     CRC-32 of every byte before it
#include <cstdint>
#include <string>
#include <vector>

#include "app/model/model_store.hpp"
#include "app/model/plant_target.hpp"
#include "app/model/series.hpp"
#include "app/model/train.hpp"
#include "shared/forward.hpp"

namespace nlsoft::model {

constexpr int kMaxPlantParts = 8;
constexpr size_t kMaxPlantText = 4096;

struct PlantPart {
  std::vector<int> outputs;  // channels, ascending
  ModelFile model;
};

struct PlantModel {
  std::string rig;
  int m = 0, n = 0, w = 0;
  double rate_hz = 0;
  std::string fit;  // the held-out free run, in words
  std::vector<PlantPart> parts;
  int channels() const { return n + w; }
};

// Throws PipelineError naming `name`: a wrong magic or version, a size that
// does not add up, a channel missing or predicted twice, a part whose model
// does not read this plant's channels.
PlantModel decode_plant_model(const std::vector<uint8_t>& bytes, const std::string& name);
std::vector<uint8_t> encode_plant_model(PlantModel& pm);
PlantModel load_plant_model(const std::string& path);
void save_plant_model(const std::string& path, PlantModel& pm);  // atomic

// The channels grouped into parts: in order, HostCapacity::n at a time.
std::vector<std::vector<int>> plant_parts(int n, int w);
// What part `outputs` trains on: the series' channels `outputs` as its
// outputs, the inputs, no sensors.
Series part_series(const Series& s, const std::vector<int>& outputs);
// The target of such a part: the rig's limits and rate; each output centred
// on the rig's rest (y) or the middle of the data's range (l), its span the
// rig's (y) or the data's range (l).
PlantTarget part_target(const PlantTarget& rig, const std::vector<Series>& runs, const std::vector<int>& outputs);

// The parts stepped together, in float as the firmware's forward pass.
class PlantSimulator {
 public:
  explicit PlantSimulator(const PlantModel& pm);
  // Every channel's history held at `channels` (n + w values: y then l),
  // every input's at `u`: a plant at rest there.
  void rest_at(const float* channels, const float* u);
  // Series row k as the newest sample: the history of rows before it.
  void start_at(const Series& s, long k);
  // u(k) applied: the channels move on to step k + 1.
  void step(const float* u);
  const float* channels() const { return hist_.data(); }  // newest: y then l
  int history() const { return depth_; }

 private:
  const PlantModel& pm_;
  int depth_ = 1, u_depth_ = 1;
  std::vector<float> hist_;  // depth x channels, newest first
  std::vector<float> u_;     // u_depth x m, newest first
  std::vector<float> next_;
  std::vector<Model<HostCapacity>> views_;
};

// The coupled free run over the last tenth of each run (rows no part was
// trained or stopped on), driven by the recorded inputs: per output y, its
// RMSE in the output's units. `rows` counts the rows scored.
struct PlantFit {
  std::vector<double> rmse;
  long rows = 0;
};
PlantFit plant_free_run(const PlantModel& pm, const std::vector<Series>& runs);
std::string plant_fit_words(const PlantFit& fit, const PlantTarget& rig);

}  // namespace nlsoft::model
