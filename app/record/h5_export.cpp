#include "app/record/h5_export.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <unistd.h>

#include "host/files/cli_error.hpp"
#include "app/h5_handle.hpp"
#include "host/files/output_file.hpp"
#include "host/files/printable.hpp"
#include "host/rig/rig_catalog.hpp"
#include "app/record/step_time.hpp"
#include "app/record/utc_time.hpp"
#include "app/record/task_space.hpp"

namespace nlsoft::console {

using host::CliError;
using host::OutputFile;
using host::Rig;
using host::load_rig_arg;
using host::printable;
using host::rig_names;

namespace {

namespace tf = protocol::telemetry_field;
constexpr float kMissing = std::numeric_limits<float>::quiet_NaN();

// Every failing HDF5 call ends here: HDF5 prints its own error stack to
// stderr unless told not to (done once per export), so the words are ours.
[[noreturn]] void fail(const std::string& what) { throw CliError("writing HDF5 failed: " + what); }

hid_t check(hid_t id, const std::string& what) {
  if (id < 0) fail(what);
  return id;
}

void check(herr_t r, const std::string& what) {
  if (r < 0) fail(what);
}

// A variable-length UTF-8 string type: what h5py reads as str and MATLAB
// as a string (fixed-length ones come back padded).
H5Handle utf8_type() {
  H5Handle t(check(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
  check(H5Tset_size(t.get(), H5T_VARIABLE), "string type");
  check(H5Tset_cset(t.get(), H5T_CSET_UTF8), "string type");
  return t;
}

void put_strings(hid_t obj, const std::string& name, const std::vector<std::string>& values, bool scalar) {
  H5Handle type = utf8_type();
  const hsize_t n = values.size();
  H5Handle space(check(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), name), H5Sclose);
  std::vector<const char*> ptrs;
  for (const auto& v : values) ptrs.push_back(v.c_str());
  H5Handle a(check(H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), name), H5Aclose);
  if (!ptrs.empty()) check(H5Awrite(a.get(), type.get(), ptrs.data()), name);
}

void put(hid_t obj, const std::string& name, const std::string& value) { put_strings(obj, name, {value}, true); }

template <class T>
void put_number(hid_t obj, const std::string& name, hid_t type, T value) {
  H5Handle space(check(H5Screate(H5S_SCALAR), name), H5Sclose);
  H5Handle a(check(H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), name), H5Aclose);
  check(H5Awrite(a.get(), type, &value), name);
}

H5Handle group(hid_t parent, const std::string& name) {
  return H5Handle(check(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), name), H5Gclose);
}

// rows x cols (cols 0: a vector of rows), row-major as C, h5py and
// MATLAB's h5read (transposed, as for every HDF5 file) expect.
H5Handle dataset(hid_t parent, const std::string& name, hid_t file_type, hid_t mem_type, const void* data, size_t rows,
                 size_t cols) {
  const hsize_t dims[2] = {rows, cols};
  H5Handle space(check(H5Screate_simple(cols == 0 ? 1 : 2, dims, nullptr), name), H5Sclose);
  H5Handle d(check(H5Dcreate2(parent, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   name),
             H5Dclose);
  if (rows > 0) check(H5Dwrite(d.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), name);
  return d;
}

void strings_dataset(hid_t parent, const std::string& name, const std::vector<std::string>& values) {
  H5Handle type = utf8_type();
  std::vector<const char*> ptrs;
  for (const auto& v : values) ptrs.push_back(v.c_str());
  dataset(parent, name, type.get(), type.get(), ptrs.data(), values.size(), 0);
}

// A dataset's columns: `names` and `units` one per column, so a script
// reads them the same way on every dataset; `unit` as well when every column
// shares one (what format 1 wrote alone then, and still the handier word).
void put_columns(hid_t obj, const std::vector<std::string>& names, const std::vector<std::string>& units) {
  if (units.empty()) return;
  put_strings(obj, "names", names, false);
  put_strings(obj, "units", units, false);
  if (std::all_of(units.begin(), units.end(), [&](const std::string& u) { return u == units[0]; }))
    put(obj, "unit", units[0]);
}

std::string sizes(int n, int m, int w) { return fmt::format("n={} m={} w={}", n, m, w); }

// A run without sensors (w 0) fits a rig that has some: it recorded none.
bool fits(const Rig& rig, const RunRow& r) { return rig.n() == r.n && rig.m() == r.m && (r.w == 0 || rig.w() == r.w); }

RigColumns columns_of(const Rig& rig, const RunRow& r) {
  RigColumns c;
  for (const auto& o : rig.outputs) c.output_names.push_back(o.name), c.output_units.push_back(o.unit);
  for (const auto& i : rig.inputs) c.input_names.push_back(i.name), c.input_units.push_back(i.unit);
  if (r.w > 0)
    for (const auto& l : rig.sensors) c.sensor_names.push_back(l.name), c.sensor_units.push_back(l.unit);
  return c;
}

// The run's own rig when the console knows it by name and its sizes are the
// run's; else no names, and `why_not` says why in a few words.
RigColumns own_rig_columns(const RunRow& r, std::string& why_not) {
  if (r.platform.empty()) {
    why_not = fmt::format("run {} names no rig", r.id);
    return {};
  }
  // Only a name in the rigs folders ($NLSOFT_RIGS, the shipped ones): a
  // platform holding '/' or ending in .toml would be taken for a path by
  // load_rig_arg, and a run's name is no path.
  const auto known = rig_names();
  if (std::find(known.begin(), known.end(), r.platform) == known.end()) {
    why_not = fmt::format("run {}'s rig \"{}\" is in no rigs folder", r.id, printable(r.platform));
    return {};
  }
  try {
    const Rig rig = load_rig_arg(r.platform);
    if (fits(rig, r)) return columns_of(rig, r);
    why_not = fmt::format("run {} has {}, the shipped rig {} {}", r.id, sizes(r.n, r.m, r.w), r.platform,
                          sizes(rig.n(), rig.m(), rig.w()));
  } catch (const std::exception&) {
    why_not = fmt::format("run {}'s rig file {} cannot be read", r.id, r.platform);
  }
  return {};
}

// One run's samples, by field; rows a field is missing from hold NaN.
struct Columnar {
  std::vector<uint64_t> k;
  std::vector<uint32_t> step, time_us;
  std::vector<double> t, t_firmware;
  std::vector<float> y_ref, y_hat, y_true, u, l, cost, compute_us;
  std::vector<uint8_t> iterations;
  std::vector<uint32_t> l_invalid;  // SENSOR_HEALTH's mask per row (rigs with sensor chips)
  std::vector<float> l_age_ms;      // NaN: no health recorded for the row
  uint8_t seen = 0;     // telemetry fields present in any row
  bool seen_l = false;  // sensors in any row (identification runs)
  bool seen_health = false;
};

Columnar read_run(RunStore& store, const RunRow& r) {
  Columnar c;
  const size_t n = size_t(r.n), m = size_t(r.m);
  StepClock clock(r.loop_rate_hz);
  // time_us is the firmware's 32-bit microsecond clock: it wraps every
  // 71.6 minutes, so t_firmware is unwrapped here, from the run's first sample.
  uint64_t high = 0;
  uint32_t last = 0;
  bool first = true;
  double t0 = 0;
  const std::map<uint32_t, SensorHealthRecord> health = store.sensor_health(r.id);
  c.seen_health = !health.empty();
  store.for_each_sample(r.id, [&](const Sample& s) {
    c.seen |= s.mask;
    c.k.push_back(s.k);
    c.step.push_back(s.has(tf::kStep) ? s.step : 0);
    c.time_us.push_back(s.has(tf::kTime) ? s.time_us : 0);
    c.t.push_back(clock.at(s.has(tf::kStep), s.step));
    if (s.has(tf::kTime)) {
      if (!first && s.time_us < last) high += uint64_t(1) << 32;
      const double us = double(high + s.time_us);
      if (first) t0 = us, first = false;
      last = s.time_us;
      c.t_firmware.push_back((us - t0) * 1e-6);
    } else {
      c.t_firmware.push_back(std::numeric_limits<double>::quiet_NaN());
    }
    auto add = [](std::vector<float>& to, bool has, const float* v, size_t count) {
      for (size_t i = 0; i < count; ++i) to.push_back(has ? v[i] : kMissing);
    };
    add(c.y_ref, s.has(tf::kYRef), s.y_ref(), n);
    add(c.y_hat, s.has(tf::kYHat), s.y_hat(), n);
    add(c.y_true, s.has(tf::kYTrue), s.y_true(), n);
    add(c.u, s.has(tf::kU), s.u(), m);
    // An invalid channel held no reading: NaN, not the 0 the firmware sent.
    const auto h = s.has(tf::kStep) ? health.find(s.step) : health.end();
    const uint32_t invalid = h == health.end() ? 0 : h->second.invalid;
    for (size_t i = 0; i < size_t(r.w); ++i) c.l.push_back(s.w > 0 && !channel_invalid(invalid, i) ? s.l[i] : kMissing);
    c.seen_l = c.seen_l || s.w > 0;
    if (c.seen_health) {
      c.l_invalid.push_back(invalid);
      c.l_age_ms.push_back(h == health.end() ? kMissing : float(h->second.age_ms));
    }
    c.cost.push_back(s.has(tf::kCost) ? s.cost : kMissing);
    c.iterations.push_back(s.has(tf::kSolver) ? s.iterations : 0);
    c.compute_us.push_back(s.has(tf::kSolver) ? s.compute_us : kMissing);
  });
  return c;
}

// The run's row as attributes, and the rig's names of its columns.
void write_run_attributes(hid_t gid, const RunRow& r, const RigColumns& names) {
  put_number<int64_t>(gid, "id", H5T_NATIVE_INT64, r.id);
  put(gid, "rig", r.platform);
  put(gid, "kind", r.kind);
  if (!r.excitation.empty()) put(gid, "excitation", r.excitation);
  put(gid, "firmware", r.firmware);
  put(gid, "started_at", r.started_at);
  put(gid, "ended_at", r.ended_at);
  put(gid, "end_reason", r.ended_at.empty() ? "unfinished" : r.end_reason);
  put(gid, "label", r.label);
  put(gid, "notes", r.notes);
  put(gid, "reference", r.reference);
  put(gid, "model_hash", fmt::format("{:08x}", r.model_hash));
  put(gid, "param_hash", fmt::format("{:08x}", r.param_hash));
  put_number<double>(gid, "loop_rate_hz", H5T_NATIVE_DOUBLE, r.loop_rate_hz);
  put_number<int32_t>(gid, "n", H5T_NATIVE_INT32, r.n);
  put_number<int32_t>(gid, "m", H5T_NATIVE_INT32, r.m);
  put_number<int32_t>(gid, "w", H5T_NATIVE_INT32, r.w);
  put_number<int32_t>(gid, "decimation", H5T_NATIVE_INT32, r.decimation);
  put_number<uint64_t>(gid, "lost_frames", H5T_NATIVE_UINT64, r.lost_frames);

  if (!names.output_names.empty()) {
    put_strings(gid, "output_names", names.output_names, false);
    put_strings(gid, "input_names", names.input_names, false);
  }
  if (!names.sensor_names.empty()) put_strings(gid, "sensor_names", names.sensor_names, false);
}

// The samples, a dataset per field the firmware sent; the fields it never
// sent are named in "absent".
void write_samples(hid_t gid, const Columnar& c, const RunRow& r, const RigColumns& names) {
  const size_t rows = c.k.size(), n = size_t(r.n), m = size_t(r.m);
  dataset(gid, "k", H5T_STD_U64LE, H5T_NATIVE_UINT64, c.k.data(), rows, 0);
  if (c.seen & tf::kStep) {
    dataset(gid, "step", H5T_STD_U32LE, H5T_NATIVE_UINT32, c.step.data(), rows, 0);
    H5Handle t = dataset(gid, "t", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, c.t.data(), rows, 0);
    put(t.get(), "unit", "s");
    put(t.get(), "description",
        "control-step time: (step - the run's first step) / loop_rate_hz (NaN: no step in the row, or no rate)");
  }
  if (c.seen & tf::kTime) {
    H5Handle t = dataset(gid, "t_firmware", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, c.t_firmware.data(), rows, 0);
    put(t.get(), "unit", "s");
    put(t.get(), "description",
        "the firmware's clock since the run's first sample (a --sim-fast simulator's is the host's)");
    H5Handle us = dataset(gid, "time_us", H5T_STD_U32LE, H5T_NATIVE_UINT32, c.time_us.data(), rows, 0);
    put(us.get(), "unit", "us");
    put(us.get(), "description", "the firmware's 32-bit microsecond clock as sent");
  }
  struct Vec {
    const char* name;
    uint8_t field;
    const std::vector<float>& data;
    size_t cols;
    const std::vector<std::string>& names;
    const std::vector<std::string>& units;
    const char* description;
  };
  const Vec vecs[] = {
      {"y_ref", tf::kYRef, c.y_ref, n, names.output_names, names.output_units, "reference r"},
      {"y_hat", tf::kYHat, c.y_hat, n, names.output_names, names.output_units, "the model's one-step prediction"},
      {"y_true", tf::kYTrue, c.y_true, n, names.output_names, names.output_units, "measured output"},
      {"u", tf::kU, c.u, m, names.input_names, names.input_units, "applied input"},
  };
  std::vector<std::string> absent;
  for (const Vec& v : vecs) {
    if (!(c.seen & v.field)) {
      absent.push_back(v.name);
      continue;
    }
    H5Handle d = dataset(gid, v.name, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, v.data.data(), rows, v.cols);
    put_columns(d.get(), v.names, v.units);
    put(d.get(), "description", v.description);
  }
  if (c.seen_l && r.w > 0) {
    H5Handle d = dataset(gid, "l", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, c.l.data(), rows, size_t(r.w));
    put_columns(d.get(), names.sensor_names, names.sensor_units);
    put(d.get(), "description", "sensors (the network's extra inputs)");
  } else if (r.w > 0) {
    absent.push_back("l");
  }
  if (c.seen_health) {
    H5Handle d = dataset(gid, "l_invalid", H5T_STD_U32LE, H5T_NATIVE_UINT32, c.l_invalid.data(), rows, 0);
    put(d.get(), "description", "bit i: sensor channel i held no valid chip sample (its l is NaN)");
    H5Handle a = dataset(gid, "l_age_ms", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, c.l_age_ms.data(), rows, 0);
    put(a.get(), "unit", "ms");
    put(a.get(), "description", "age of the oldest valid chip sample (NaN: no health recorded for the row)");
  }
  if (c.seen & tf::kCost) dataset(gid, "cost", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, c.cost.data(), rows, 0);
  else absent.push_back("cost");
  if (c.seen & tf::kSolver) {
    dataset(gid, "iterations", H5T_STD_U8LE, H5T_NATIVE_UINT8, c.iterations.data(), rows, 0);
    H5Handle d = dataset(gid, "compute_us", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, c.compute_us.data(), rows, 0);
    put(d.get(), "unit", "us");
  } else {
    absent.push_back("iterations");
    absent.push_back("compute_us");
  }
  // Fields the firmware never sent (y_true on a rig without a measured
  // output): named, so a script tells "not measured" from "forgotten".
  put_strings(gid, "absent", absent, false);
}

// Gaps: where frames were lost, after which sample, for how long, why.
void write_gaps(hid_t gid, RunStore& store, const RunRow& r) {
  const auto gaps = store.gaps(r.id);
  H5Handle gg = group(gid, "gaps");
  std::vector<uint64_t> after, lost;
  std::vector<double> seconds;
  std::vector<std::string> reason, when;
  for (const auto& g2 : gaps) {
    after.push_back(g2.after_k);
    lost.push_back(g2.lost_frames);
    seconds.push_back(g2.duration_s < 0 ? std::numeric_limits<double>::quiet_NaN() : g2.duration_s);
    reason.push_back(g2.reason);
    when.push_back(g2.t);
  }
  dataset(gg.get(), "after_k", H5T_STD_U64LE, H5T_NATIVE_UINT64, after.data(), after.size(), 0);
  dataset(gg.get(), "lost_frames", H5T_STD_U64LE, H5T_NATIVE_UINT64, lost.data(), lost.size(), 0);
  H5Handle dur = dataset(gg.get(), "duration_s", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, seconds.data(), seconds.size(), 0);
  put(dur.get(), "unit", "s");
  strings_dataset(gg.get(), "reason", reason);
  strings_dataset(gg.get(), "at", when);
}

// Parameters: the values at the start as attributes, changes as rows.
void write_parameters(hid_t gid, RunStore& store, const RunRow& r) {
  H5Handle pg = group(gid, "parameters");
  std::vector<double> at;
  std::vector<std::string> pname, pvalue;
  for (const auto& p : store.params(r.id)) {
    if (p.at_start) {
      put(pg.get(), p.name, p.value);
    } else {
      at.push_back(p.t);
      pname.push_back(p.name);
      pvalue.push_back(p.value);
    }
  }
  H5Handle changes = group(pg.get(), "changes");
  H5Handle ct = dataset(changes.get(), "t", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, at.data(), at.size(), 0);
  put(ct.get(), "unit", "s");
  strings_dataset(changes.get(), "name", pname);
  strings_dataset(changes.get(), "value", pvalue);
}

uint64_t write_run(hid_t file, RunStore& store, const RunRow& r, const RigColumns& names) {
  H5Handle g = group(file, fmt::format("run_{}", r.id));
  const hid_t gid = g.get();
  write_run_attributes(gid, r, names);
  const Columnar c = read_run(store, r);
  put_number<uint64_t>(gid, "samples", H5T_NATIVE_UINT64, c.k.size());
  write_samples(gid, c, r, names);
  write_gaps(gid, store, r);
  write_parameters(gid, store, r);
  return c.k.size();
}

}  // namespace

H5Export export_runs_h5(RunStore& store, const std::vector<int64_t>& ids, const std::string& path,
                        const std::string& rig_arg) {
  if (ids.empty()) throw CliError("runs export: name at least one run");
  std::vector<RunRow> runs;
  std::set<int64_t> seen;
  for (int64_t id : ids) {
    if (!seen.insert(id).second) throw CliError(fmt::format("runs export: run {} is named twice", id));
    runs.push_back(store.run(id));  // "no run N" before anything is written
  }
  // Every run's channel names before the file is begun: a --rig that is not
  // the runs' is refused with nothing written.
  std::vector<RigColumns> columns;
  std::vector<std::string> unnamed;
  if (!rig_arg.empty()) {
    const Rig rig = load_rig_arg(rig_arg);
    for (const RunRow& r : runs) {
      if (!fits(rig, r))
        throw CliError(fmt::format("runs export --rig {}: the rig {} has {}, run {} (rig \"{}\") has {}: its "
                                   "channels are another rig's",
                                   printable(rig_arg), printable(rig.name), sizes(rig.n(), rig.m(), rig.w()), r.id,
                                   printable(r.platform), sizes(r.n, r.m, r.w)));
      columns.push_back(columns_of(rig, r));
    }
  } else {
    for (const RunRow& r : runs) {
      std::string why_not;
      columns.push_back(own_rig_columns(r, why_not));
      if (!why_not.empty()) unnamed.push_back(why_not);
    }
  }
  H5Export report;
  if (!unnamed.empty()) {
    report.unnamed = "exported without channel names and units: ";
    for (size_t i = 0; i < unnamed.size(); ++i) report.unnamed += (i ? "; " : "") + unnamed[i];
    report.unnamed += " (--rig FILE names them)";
  }
  // Checked (a directory, a loop of links) before the work, not after.
  OutputFile out(path);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // Built in memory (HDF5's core driver, no backing file) and written in
  // one piece through OutputFile: the file appears whole or not at all, and
  // a pipe or /dev/stdout gets it as well as a regular file does.
  std::vector<char> image;
  {
    H5Handle fapl(check(H5Pcreate(H5P_FILE_ACCESS), "file access"), H5Pclose);
    check(H5Pset_fapl_core(fapl.get(), 1 << 20, 0), "core driver");
    const std::string name = "nlsoft-export-" + std::to_string(::getpid());
    H5Handle file(check(H5Fcreate(name.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl.get()), "create"), H5Fclose);
    put(file.get(), "format", "nlsoft runs");
    // 2: t became the step time; version 1's t (the firmware clock) is t_firmware.
    put_number<int32_t>(file.get(), "format_version", H5T_NATIVE_INT32, 2);
    put(file.get(), "exported_at", utc_now());
    for (size_t i = 0; i < runs.size(); ++i) report.samples += write_run(file.get(), store, runs[i], columns[i]);
    check(H5Fflush(file.get(), H5F_SCOPE_GLOBAL), "flush");
    const ssize_t size = H5Fget_file_image(file.get(), nullptr, 0);
    if (size <= 0) fail("file image");
    image.resize(size_t(size));
    if (H5Fget_file_image(file.get(), image.data(), image.size()) != size) fail("file image");
  }
  if (std::fwrite(image.data(), 1, image.size(), out.get()) != image.size())
    throw CliError(fmt::format("writing {} failed", path));
  out.commit();
  return report;
}

}  // namespace nlsoft::console
