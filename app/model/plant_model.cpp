#include "app/model/plant_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "app/model/atomic_file.hpp"
#include "app/model/error.hpp"
#include "shared/crc32.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::model {

namespace {

constexpr uint8_t kPlantFormat = 1;
constexpr size_t kPlantHeader = 20;
constexpr size_t kPlantMax =
    kPlantHeader + 2 * kMaxPlantText + size_t(kMaxPlantParts) * (1 + HostCapacity::n + 4 + model_file_max<HostCapacity>()) + 4;

void put16(std::vector<uint8_t>& b, size_t v) {
  b.push_back(uint8_t(v));
  b.push_back(uint8_t(v >> 8));
}
void put32(std::vector<uint8_t>& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
}
uint32_t rd32(const uint8_t* p) { return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24; }

// The bytes read front to back: every size is checked here, against what is
// left, before it is used.
class Reader {
 public:
  Reader(const std::vector<uint8_t>& b, size_t end, const std::string& name) : b_(b), end_(end), name_(name) {}
  const uint8_t* take(size_t len, const char* what) {
    if (len > end_ - at_)
      throw PipelineError(fmt::format("'{}' is not a valid plant model: {} ({} bytes at offset {}) runs past its end",
                                      name_, what, len, at_));
    const uint8_t* p = b_.data() + at_;
    at_ += len;
    return p;
  }
  size_t left() const { return end_ - at_; }
  size_t at() const { return at_; }

 private:
  const std::vector<uint8_t>& b_;
  size_t end_, at_ = 0;
  const std::string& name_;
};

}  // namespace

std::vector<uint8_t> encode_plant_model(PlantModel& pm) {
  if (pm.rig.empty() || pm.rig.size() > kMaxPlantText || pm.fit.size() > kMaxPlantText)
    throw PipelineError("a plant model's rig name and fit must each take 1 to " + std::to_string(kMaxPlantText) + " bytes");
  if (pm.parts.empty() || pm.parts.size() > size_t(kMaxPlantParts))
    throw PipelineError("a plant model has 1 to " + std::to_string(kMaxPlantParts) + " parts");
  std::vector<uint8_t> b{'N', 'L', 'S', 'P', kPlantFormat, uint8_t(pm.m), uint8_t(pm.n), uint8_t(pm.w),
                         uint8_t(pm.parts.size()), 0, 0, 0};
  const float rate = float(pm.rate_hz);
  uint32_t rate_bits = 0;
  std::memcpy(&rate_bits, &rate, 4);
  put32(b, rate_bits);
  put16(b, pm.rig.size());
  put16(b, pm.fit.size());
  b.insert(b.end(), pm.rig.begin(), pm.rig.end());
  b.insert(b.end(), pm.fit.begin(), pm.fit.end());
  for (PlantPart& part : pm.parts) {
    b.push_back(uint8_t(part.outputs.size()));
    for (int c : part.outputs) b.push_back(uint8_t(c));
    const std::vector<uint8_t> model = encode_model(part.model);
    put32(b, uint32_t(model.size()));
    b.insert(b.end(), model.begin(), model.end());
  }
  put32(b, crc32(b.data(), b.size()));
  return b;
}

PlantModel decode_plant_model(const std::vector<uint8_t>& bytes, const std::string& name) {
  auto bad = [&](const std::string& why) {
    return PipelineError(fmt::format("'{}' is not a valid plant model: {}", name, why));
  };
  if (bytes.size() < kPlantHeader + 4 || std::memcmp(bytes.data(), "NLSP", 4) != 0)
    throw bad("no NLSP header (train --plant writes one)");
  if (bytes[4] != kPlantFormat) throw bad(fmt::format("format {}, this console reads format {}", bytes[4], kPlantFormat));
  const size_t body = bytes.size() - 4;
  if (crc32(bytes.data(), body) != rd32(bytes.data() + body)) throw bad("its CRC-32 does not match (a damaged file)");
  Reader r(bytes, body, name);
  const uint8_t* h = r.take(kPlantHeader, "the header");
  PlantModel pm;
  pm.m = h[5], pm.n = h[6], pm.w = h[7];
  const int parts = h[8];
  if (pm.m < 1 || pm.m > HostCapacity::m || pm.n < 1 || pm.n > HostCapacity::n || pm.w > HostCapacity::w)
    throw bad(fmt::format("m = {}, n = {}, w = {} is past the console's capacity", pm.m, pm.n, pm.w));
  if (parts < 1 || parts > kMaxPlantParts) throw bad(fmt::format("{} parts (1 to {})", parts, kMaxPlantParts));
  float rate = 0;
  std::memcpy(&rate, h + 12, 4);
  if (!(rate > 0 && std::isfinite(rate))) throw bad("its control rate is not a positive number");
  pm.rate_hz = rate;
  const size_t R = size_t(h[16]) | size_t(h[17]) << 8, F = size_t(h[18]) | size_t(h[19]) << 8;
  if (R < 1 || R > kMaxPlantText || F > kMaxPlantText) throw bad("its rig name or fit is too long");
  const uint8_t* rig = r.take(R, "the rig's name");
  pm.rig.assign(rig, rig + R);
  const uint8_t* fit = r.take(F, "the fit");
  pm.fit.assign(fit, fit + F);
  std::vector<int> owner(size_t(pm.channels()), -1);
  for (int i = 0; i < parts; ++i) {
    PlantPart part;
    const int c = *r.take(1, "a part's channel count");
    if (c < 1 || c > HostCapacity::n || c > pm.channels())
      throw bad(fmt::format("part {} predicts {} channels (1 to {})", i + 1, c, std::min(HostCapacity::n, pm.channels())));
    const uint8_t* ch = r.take(size_t(c), "a part's channels");
    for (int j = 0; j < c; ++j) {
      if (ch[j] >= pm.channels()) throw bad(fmt::format("part {} names channel {} of {}", i + 1, ch[j], pm.channels()));
      if (owner[ch[j]] >= 0) throw bad(fmt::format("channel {} is predicted by parts {} and {}", ch[j], owner[ch[j]] + 1, i + 1));
      if (j > 0 && ch[j] <= ch[j - 1]) throw bad(fmt::format("part {}'s channels are not ascending", i + 1));
      owner[ch[j]] = i;
      part.outputs.push_back(ch[j]);
    }
    const uint32_t L = rd32(r.take(4, "a part's model length"));
    if (L > model_file_max<HostCapacity>()) throw bad(fmt::format("part {}'s model of {} bytes is past the console's largest", i + 1, L));
    const uint8_t* mb = r.take(L, "a part's model");
    part.model = decode_model(std::vector<uint8_t>(mb, mb + L), fmt::format("{} (part {})", name, i + 1));
    const Model<HostCapacity>& M = part.model.shape;
    if (M.m != pm.m || M.n != c || M.w != 0)
      throw bad(fmt::format("part {}'s model reads m = {}, n = {}, w = {}, not m = {}, n = {}, w = 0 (its {} channels "
                            "from the inputs alone)",
                            i + 1, M.m, M.n, M.w, pm.m, c, c));
    pm.parts.push_back(std::move(part));
  }
  if (r.left() != 0) throw bad(fmt::format("{} bytes after its last part", r.left()));
  for (int c = 0; c < pm.channels(); ++c)
    if (owner[size_t(c)] < 0) throw bad(fmt::format("no part predicts channel {}", c));
  return pm;
}

PlantModel load_plant_model(const std::string& path) {
  const std::string text = read_text_file(path, {"plant model", kPlantMax, false});
  return decode_plant_model(std::vector<uint8_t>(text.begin(), text.end()), path);
}

void save_plant_model(const std::string& path, PlantModel& pm) { write_file_atomic(path, encode_plant_model(pm)); }

std::vector<std::vector<int>> plant_parts(int n, int w) {
  std::vector<std::vector<int>> parts;
  for (int c = 0; c < n + w; ++c) {
    if (parts.empty() || int(parts.back().size()) == HostCapacity::n) parts.emplace_back();
    parts.back().push_back(c);
  }
  return parts;
}

namespace {

double channel(const Series& s, long r, int c) { return c < s.n ? s.y(r, c) : s.l(r, c - s.n); }

}  // namespace

Series part_series(const Series& s, const std::vector<int>& outputs) {
  Series p;
  p.resize(s.rows(), s.m, int(outputs.size()), 0);
  p.time = s.time;
  p.u = s.u;
  p.breaks = s.breaks;
  p.name = s.name;
  for (long r = 0; r < s.rows(); ++r)
    for (size_t j = 0; j < outputs.size(); ++j) p.y(r, Eigen::Index(j)) = channel(s, r, outputs[j]);
  return p;
}

PlantTarget part_target(const PlantTarget& rig, const std::vector<Series>& runs, const std::vector<int>& outputs) {
  PlantTarget t = rig;
  t.n = int(outputs.size());
  t.w = 0;
  t.layers.clear();  // the defaults: larger than a controller's model, chosen on held-out rows
  t.plant = TargetPlant::None;
  t.y_rest.clear(), t.y_span.clear(), t.y_names.clear();
  for (int c : outputs) {
    if (c < rig.n) {
      t.y_rest.push_back(rig.y_rest[size_t(c)]);
      t.y_span.push_back(rig.y_span[size_t(c)]);
      t.y_names.push_back(size_t(c) < rig.y_names.size() ? rig.y_names[size_t(c)] : "y" + std::to_string(c));
      continue;
    }
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (const Series& s : runs)
      for (long r = 0; r < s.rows(); ++r) lo = std::min(lo, channel(s, r, c)), hi = std::max(hi, channel(s, r, c));
    if (!(hi >= lo)) lo = hi = 0;
    t.y_rest.push_back(0.5 * (lo + hi));
    t.y_span.push_back(hi > lo ? hi - lo : 1.0);
    t.y_names.push_back("l" + std::to_string(c - rig.n));
  }
  if (outputs.front() >= rig.n) t.y_unit.clear();
  return t;
}

PlantSimulator::PlantSimulator(const PlantModel& pm) : pm_(pm) {
  for (const PlantPart& p : pm.parts) {
    views_.push_back(p.model.view());
    depth_ = std::max(depth_, int(p.model.shape.dd));
    u_depth_ = std::max(u_depth_, int(p.model.shape.nd));
  }
  hist_.assign(size_t(depth_ * pm.channels()), 0.0f);
  u_.assign(size_t(u_depth_ * pm.m), 0.0f);
  next_.assign(size_t(pm.channels()), 0.0f);
}

void PlantSimulator::rest_at(const float* channels, const float* u) {
  const int C = pm_.channels();
  for (int d = 0; d < depth_; ++d) std::copy(channels, channels + C, hist_.begin() + d * C);
  for (int d = 0; d < u_depth_; ++d) std::copy(u, u + pm_.m, u_.begin() + d * pm_.m);
}

void PlantSimulator::start_at(const Series& s, long k) {
  const int C = pm_.channels();
  for (int d = 0; d < depth_; ++d)
    for (int c = 0; c < C; ++c) hist_[size_t(d * C + c)] = float(channel(s, std::max(0L, k - d), c));
  // u(k-1), u(k-2), ...: step() pushes u(k) in front of them.
  for (int d = 0; d < u_depth_; ++d)
    for (int i = 0; i < pm_.m; ++i) u_[size_t(d * pm_.m + i)] = float(s.u(std::max(0L, k - 1 - d), i));
}

void PlantSimulator::step(const float* u) {
  const int C = pm_.channels(), m = pm_.m;
  std::copy_backward(u_.begin(), u_.end() - m, u_.end());
  std::copy(u, u + m, u_.begin());
  ForwardScratch<HostCapacity, float> scratch;
  float x[Dims<HostCapacity>::p], y[HostCapacity::n];
  for (size_t i = 0; i < pm_.parts.size(); ++i) {
    const Model<HostCapacity>& M = views_[i];
    const std::vector<int>& out = pm_.parts[i].outputs;
    int at = 0;
    for (int d = 0; d < M.nd; ++d)
      for (int j = 0; j < m; ++j) x[at++] = u_[size_t(d * m + j)];
    for (int d = 0; d < M.dd; ++d)
      for (int c : out) x[at++] = hist_[size_t(d * C + c)];
    forward(M, x, y, scratch);
    for (size_t j = 0; j < out.size(); ++j) next_[size_t(out[j])] = y[j];
  }
  std::copy_backward(hist_.begin(), hist_.end() - C, hist_.end());
  std::copy(next_.begin(), next_.end(), hist_.begin());
}

PlantFit plant_free_run(const PlantModel& pm, const std::vector<Series>& runs) {
  PlantFit fit;
  fit.rmse.assign(size_t(pm.n), 0.0);
  PlantSimulator sim(pm);
  std::vector<float> u(size_t(pm.m));
  for (const Series& s : runs) {
    // The test part of train's ten-fold split, cut where the series has a gap.
    const long begin = s.rows() - s.rows() / 10;
    for (long k = begin; k + 1 < s.rows(); ++k) {
      const bool gap = std::find(s.breaks.begin(), s.breaks.end(), k + 1) != s.breaks.end();
      if (k == begin) sim.start_at(s, k);
      for (int i = 0; i < pm.m; ++i) u[size_t(i)] = float(s.u(k, i));
      sim.step(u.data());
      if (gap) {
        sim.start_at(s, k + 1);
        continue;
      }
      for (int j = 0; j < pm.n; ++j) {
        const double e = double(sim.channels()[j]) - s.y(k + 1, j);
        fit.rmse[size_t(j)] += e * e;
      }
      ++fit.rows;
    }
  }
  for (double& e : fit.rmse) e = fit.rows > 0 ? std::sqrt(e / double(fit.rows)) : std::nan("");
  return fit;
}

std::string plant_fit_words(const PlantFit& fit, const PlantTarget& rig) {
  std::string out = fmt::format("free run of the last tenth of each run ({} steps, held out of training):", fit.rows);
  for (size_t j = 0; j < fit.rmse.size(); ++j) {
    const std::string name = j < rig.y_names.size() ? rig.y_names[j] : "y" + std::to_string(j);
    out += fmt::format(" {} RMSE {:.4g}{}", name, fit.rmse[j], rig.y_unit.empty() ? "" : " " + rig.y_unit);
    if (j < rig.y_span.size() && rig.y_span[j] > 0) out += fmt::format(" ({:.2f} % of its span)", 100.0 * fit.rmse[j] / rig.y_span[j]);
    out += j + 1 < fit.rmse.size() ? "," : "";
  }
  return out;
}

}  // namespace nlsoft::model
