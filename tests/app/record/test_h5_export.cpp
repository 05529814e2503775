// `runs export ... --h5`: runs written by the recorder come back from the
// file through HDF5's own reader, dataset by dataset and attribute by
// attribute; gaps and fields the firmware never sent stay visible; t is the
// step time; the rig's names and units label the columns (or the export says
// why not); several runs in one CSV carry a run column; bad requests write
// nothing.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include <fstream>
#include <map>
#include <sstream>

#include "app/h5_handle.hpp"
#include "host/rig/rig_catalog.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {

using host::Rig;
using host::load_rig_arg;
using host::rig_path;

namespace {

using nlsoft::test::contains;

namespace tf = protocol::telemetry_field;
using test::run_process;
using test::shell_quote;

bool exists(const std::string& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0;
}

// A hasel run (3 outputs, 6 inputs) of 100 samples whose firmware clock
// wraps at sample 60, with a gap after sample 49 and one parameter change;
// with_y_true false: a run on a rig without a measured output.
int64_t record_run(const std::string& db, bool with_y_true, std::vector<Sample>& written) {
  Recorder r(db);
  RunInfo ri;
  ri.platform = "hasel";
  ri.firmware = "nlsoft-fw 1.2.0";
  ri.label = "h5 test";
  ri.model_hash = 0x1234abcd;
  ri.n = 3;
  ri.m = 6;
  ri.loop_rate_hz = 100;
  ri.params = {{"Q", "1 1 1"}, {"Lambda", "0.5"}};
  const int64_t id = r.begin_run(ri);
  const uint32_t wrap_at = 60;
  for (uint32_t k = 0; k < 100; ++k) {
    Sample s;
    s.k = k;
    s.n = 3;
    s.m = 6;
    s.mask = with_y_true ? tf::kAll : uint8_t(tf::kAll & ~tf::kYTrue);
    if (k == 7) s.mask = uint8_t(tf::kStep | tf::kTime | tf::kYRef);  // one sparse row
    s.step = k;
    s.time_us = uint32_t(uint64_t(0xFFFFFFFFu) - (wrap_at - 1) * 10000u + k * 10000u);  // wraps at k = 60
    for (int i = 0; i < 3; ++i) {
      s.y_ref()[i] = float(k) + 0.25f * float(i);
      s.y_hat()[i] = -float(k) - float(i);
      s.y_true()[i] = 3.5f * float(i + 1) + float(k);
    }
    for (int j = 0; j < 6; ++j) s.u()[j] = 0.1f * float(j) + 0.001f * float(k);
    s.cost = 10.0f + float(k);
    s.iterations = uint8_t(1 + k % 4);
    s.compute_us = 20.0f + float(k % 3);
    r.add_sample(id, s);
    written.push_back(s);
    if (k == 49) r.add_gap(id, 49, 12, "link down: test", 0.5);
  }
  r.add_param_change(id, 0.75, "Lambda", "2");
  r.end_run(id, "completed", 100, 12);
  r.flush();
  return id;
}

std::string string_attr(hid_t obj, const char* name) {
  H5Handle a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  if (!a.ok()) return "<missing>";
  H5Handle type(H5Aget_type(a.get()), H5Tclose);
  char* p = nullptr;
  H5Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem.get(), H5T_VARIABLE);
  H5Tset_cset(mem.get(), H5T_CSET_UTF8);
  if (H5Aread(a.get(), mem.get(), &p) < 0) return "<unreadable>";
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

std::vector<std::string> strings(hid_t obj, const char* name, bool dataset) {
  H5Handle h(dataset ? H5Dopen2(obj, name, H5P_DEFAULT) : H5Aopen(obj, name, H5P_DEFAULT),
             dataset ? H5Dclose : H5Aclose);
  if (!h.ok()) return {"<missing>"};
  H5Handle space(dataset ? H5Dget_space(h.get()) : H5Aget_space(h.get()), H5Sclose);
  std::vector<char*> ptrs(size_t(H5Sget_simple_extent_npoints(space.get())), nullptr);
  H5Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(mem.get(), H5T_VARIABLE);
  H5Tset_cset(mem.get(), H5T_CSET_UTF8);
  if (!ptrs.empty()) {
    if ((dataset ? H5Dread(h.get(), mem.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data())
                 : H5Aread(h.get(), mem.get(), ptrs.data())) < 0)
      return {"<unreadable>"};
  }
  std::vector<std::string> out;
  for (char* p : ptrs) out.emplace_back(p ? p : ""), H5free_memory(p);
  return out;
}

template <class T>
T number_attr(hid_t obj, const char* name, hid_t type) {
  T v{};
  H5Handle a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  EXPECT_TRUE(a.ok()) << name;
  if (a.ok()) {
    EXPECT_GE(H5Aread(a.get(), type, &v), 0) << name;
  }
  return v;
}

// A dataset's values and shape (rows, cols; cols 0 for a vector).
template <class T>
std::vector<T> read(hid_t g, const char* name, hid_t type, size_t& rows, size_t& cols) {
  rows = cols = 0;
  H5Handle d(H5Dopen2(g, name, H5P_DEFAULT), H5Dclose);
  if (!d.ok()) return {};
  H5Handle space(H5Dget_space(d.get()), H5Sclose);
  hsize_t dims[2] = {0, 0};
  const int rank = H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  rows = size_t(dims[0]);
  cols = rank == 2 ? size_t(dims[1]) : 0;
  std::vector<T> v(rows * std::max<size_t>(cols, 1));
  if (!v.empty()) {
    EXPECT_GE(H5Dread(d.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0) << name;
  }
  return v;
}

bool has_link(hid_t g, const char* name) { return H5Lexists(g, name, H5P_DEFAULT) > 0; }

class H5Export : public ::testing::Test {
 protected:
  void SetUp() override { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
  test::ProcessResult runs(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " runs " + args + " --db " + shell_quote(db()));
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(H5Export, EveryDatasetAndAttributeOfTwoRunsReadsBackWithGapsAndUnits) {
  std::vector<Sample> a, b;
  const int64_t ida = record_run(db(), true, a);
  const int64_t idb = record_run(db(), false, b);
  const std::string out = dir_.file("runs.h5");
  const auto r = runs(fmt::format("export {} {} --h5 {}", ida, idb, shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "200 samples written")) << r.output;

  H5Handle f(H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(f.ok()) << "HDF5 cannot open what was written";
  EXPECT_EQ(string_attr(f.get(), "format"), "nlsoft runs");
  EXPECT_EQ(number_attr<int32_t>(f.get(), "format_version", H5T_NATIVE_INT32), 2);

  H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", ida).c_str(), H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(string_attr(g.get(), "rig"), "hasel");
  EXPECT_EQ(string_attr(g.get(), "firmware"), "nlsoft-fw 1.2.0");
  EXPECT_EQ(string_attr(g.get(), "model_hash"), "1234abcd");
  EXPECT_EQ(string_attr(g.get(), "label"), "h5 test");
  EXPECT_EQ(string_attr(g.get(), "end_reason"), "completed");
  EXPECT_EQ(number_attr<double>(g.get(), "loop_rate_hz", H5T_NATIVE_DOUBLE), 100.0);
  EXPECT_EQ(number_attr<int32_t>(g.get(), "n", H5T_NATIVE_INT32), 3);
  EXPECT_EQ(number_attr<int32_t>(g.get(), "m", H5T_NATIVE_INT32), 6);
  EXPECT_EQ(number_attr<uint64_t>(g.get(), "samples", H5T_NATIVE_UINT64), 100u);
  EXPECT_EQ(strings(g.get(), "output_names", false).size(), 3u);
  EXPECT_EQ(strings(g.get(), "input_names", false).size(), 6u);
  EXPECT_TRUE(strings(g.get(), "absent", false).empty());

  size_t rows = 0, cols = 0;
  const auto k = read<uint64_t>(g.get(), "k", H5T_NATIVE_UINT64, rows, cols);
  ASSERT_EQ(rows, 100u);
  EXPECT_EQ(cols, 0u);
  const auto t = read<double>(g.get(), "t", H5T_NATIVE_DOUBLE, rows, cols);
  ASSERT_EQ(rows, 100u);
  for (size_t i = 0; i < 100; ++i) EXPECT_EQ(t[i], double(i) / 100.0) << i;  // step i at 100 Hz
  const auto t_fw = read<double>(g.get(), "t_firmware", H5T_NATIVE_DOUBLE, rows, cols);
  ASSERT_EQ(rows, 100u);
  // The 32-bit microsecond clock wrapped at sample 60: t_firmware goes on rising.
  for (size_t i = 0; i < 100; ++i) EXPECT_NEAR(t_fw[i], 0.01 * double(i), 1e-9) << i;
  const auto y_true = read<float>(g.get(), "y_true", H5T_NATIVE_FLOAT, rows, cols);
  ASSERT_EQ(rows, 100u);
  ASSERT_EQ(cols, 3u);
  const auto u = read<float>(g.get(), "u", H5T_NATIVE_FLOAT, rows, cols);
  ASSERT_EQ(cols, 6u);
  const auto y_ref = read<float>(g.get(), "y_ref", H5T_NATIVE_FLOAT, rows, cols);
  const auto cost = read<float>(g.get(), "cost", H5T_NATIVE_FLOAT, rows, cols);
  const auto it = read<uint8_t>(g.get(), "iterations", H5T_NATIVE_UINT8, rows, cols);
  for (size_t i = 0; i < 100; ++i) {
    EXPECT_EQ(k[i], i);
    EXPECT_EQ(y_ref[i * 3 + 2], a[i].y_ref()[2]);
    if (i == 7) {  // the sparse row: what it lacked is NaN, not a made-up 0
      EXPECT_TRUE(std::isnan(y_true[i * 3])) << y_true[i * 3];
      EXPECT_TRUE(std::isnan(u[i * 6 + 5]));
      EXPECT_TRUE(std::isnan(cost[i]));
      continue;
    }
    for (int j = 0; j < 3; ++j) EXPECT_EQ(y_true[i * 3 + j], a[i].y_true()[j]) << i;
    for (int j = 0; j < 6; ++j) EXPECT_EQ(u[i * 6 + j], a[i].u()[j]) << i;
    EXPECT_EQ(cost[i], a[i].cost);
    EXPECT_EQ(it[i], a[i].iterations);
  }
  {
    H5Handle d(H5Dopen2(g.get(), "y_true", H5P_DEFAULT), H5Dclose);
    EXPECT_EQ(string_attr(d.get(), "unit"), "mm");
    H5Handle ts(H5Dopen2(g.get(), "t", H5P_DEFAULT), H5Dclose);
    EXPECT_EQ(string_attr(ts.get(), "unit"), "s");
  }
  // The gap, as recorded.
  H5Handle gaps(H5Gopen2(g.get(), "gaps", H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(gaps.ok());
  const auto after = read<uint64_t>(gaps.get(), "after_k", H5T_NATIVE_UINT64, rows, cols);
  ASSERT_EQ(rows, 1u);
  EXPECT_EQ(after[0], 49u);
  EXPECT_EQ(read<uint64_t>(gaps.get(), "lost_frames", H5T_NATIVE_UINT64, rows, cols)[0], 12u);
  EXPECT_EQ(read<double>(gaps.get(), "duration_s", H5T_NATIVE_DOUBLE, rows, cols)[0], 0.5);
  EXPECT_EQ(strings(gaps.get(), "reason", true), std::vector<std::string>{"link down: test"});
  // Parameters at the start, and the change.
  H5Handle params(H5Gopen2(g.get(), "parameters", H5P_DEFAULT), H5Gclose);
  EXPECT_EQ(string_attr(params.get(), "Q"), "1 1 1");
  EXPECT_EQ(string_attr(params.get(), "Lambda"), "0.5");
  H5Handle changes(H5Gopen2(params.get(), "changes", H5P_DEFAULT), H5Gclose);
  EXPECT_EQ(strings(changes.get(), "name", true), std::vector<std::string>{"Lambda"});
  EXPECT_EQ(strings(changes.get(), "value", true), std::vector<std::string>{"2"});
  EXPECT_EQ(read<double>(changes.get(), "t", H5T_NATIVE_DOUBLE, rows, cols)[0], 0.75);

  // The second run had no measured output: no y_true, and it says so.
  H5Handle g2(H5Gopen2(f.get(), fmt::format("run_{}", idb).c_str(), H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(g2.ok());
  EXPECT_FALSE(has_link(g2.get(), "y_true"));
  EXPECT_TRUE(has_link(g2.get(), "y_hat"));
  EXPECT_EQ(strings(g2.get(), "absent", false), std::vector<std::string>{"y_true"});
}

// An identification run keeps its sensors: l is a dataset [N, w] with the
// rig's sensor names, and the run says it is one and with what signal.
TEST_F(H5Export, AnIdentificationRunsSensorsAreADatasetOfTheirOwn) {
  int64_t id = 0;
  {
    Recorder r(db());
    RunInfo ri;
    ri.platform = "hasel";
    ri.kind = "ident";
    ri.excitation = R"({"signal":"prbs","seed":7})";
    ri.n = 3;
    ri.m = 6;
    ri.w = 18;
    ri.loop_rate_hz = 130;
    id = r.begin_run(ri);
    for (uint32_t k = 0; k < 20; ++k) {
      Sample s;
      s.k = k;
      s.n = 3;
      s.m = 6;
      s.w = 18;
      s.mask = uint8_t(tf::kStep | tf::kTime | tf::kYTrue | tf::kU);
      s.step = k;
      s.time_us = k * 7692;
      for (int i = 0; i < 18; ++i) s.l[i] = float(k) + 0.5f * float(i);
      r.add_sample(id, s);
    }
    r.end_run(id, "completed", 20, 0);
    r.flush();
  }
  const std::string out = dir_.file("ident.h5");
  const auto r = runs(fmt::format("export {} --h5 {}", id, shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  H5Handle f(H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(f.ok());
  H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", id).c_str(), H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(string_attr(g.get(), "kind"), "ident");
  EXPECT_EQ(string_attr(g.get(), "excitation"), R"({"signal":"prbs","seed":7})");
  EXPECT_EQ(number_attr<int32_t>(g.get(), "w", H5T_NATIVE_INT32), 18);
  EXPECT_EQ(strings(g.get(), "sensor_names", false).size(), 18u);
  size_t rows = 0, cols = 0;
  const auto l = read<float>(g.get(), "l", H5T_NATIVE_FLOAT, rows, cols);
  ASSERT_EQ(rows, 20u);
  ASSERT_EQ(cols, 18u);
  for (size_t k = 0; k < 20; ++k)
    for (size_t i = 0; i < 18; ++i) EXPECT_EQ(l[k * 18 + i], float(k) + 0.5f * float(i));
  // Never sent by an identification run: named as absent.
  const auto absent = strings(g.get(), "absent", false);
  EXPECT_NE(std::find(absent.begin(), absent.end(), "y_hat"), absent.end());
  EXPECT_NE(std::find(absent.begin(), absent.end(), "cost"), absent.end());
}

// A rig with sensor chips: a channel the firmware flagged invalid at a step
// is no reading (empty in CSV, NaN in HDF5), and each row says which were
// invalid and how old the chips' samples were; a step whose health was not
// recorded has its readings and empty health cells.
TEST_F(H5Export, SensorHealthMarksInvalidChannelsInBothFormats) {
  int64_t id = 0;
  {
    Recorder r(db());
    RunInfo ri;
    ri.platform = "chips";
    ri.kind = "ident";
    ri.n = 1;
    ri.m = 1;
    ri.w = 3;
    ri.loop_rate_hz = 100;
    id = r.begin_run(ri);
    for (uint32_t k = 0; k < 4; ++k) {
      Sample s;
      s.k = k;
      s.n = 1;
      s.m = 1;
      s.w = 3;
      s.mask = uint8_t(tf::kStep | tf::kU);
      s.step = 10 + k;
      for (int i = 0; i < 3; ++i) s.l[i] = float(k) + 0.25f * float(i + 1);
      r.add_sample(id, s);
    }
    r.add_sensor_health(id, 11, 0x2u, 7);  // l1 invalid at step 11
    r.add_sensor_health(id, 12, 0x0u, 3);
    r.end_run(id, "completed", 4, 0);
    r.flush();
  }
  const std::string csv = dir_.file("health.csv");
  ASSERT_EQ(runs(fmt::format("export {} --csv {}", id, shell_quote(csv))).code, 0);
  std::ifstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line.substr(line.size() - std::string(",l0,l1,l2,l_invalid,l_age_ms,t").size()),
            ",l0,l1,l2,l_invalid,l_age_ms,t")
      << line;
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);
  auto tail = [](const std::string& row, int cells) {
    size_t at = row.size();
    for (int i = 0; i < cells; ++i) at = row.rfind(',', at - 1);
    return row.substr(at + 1);
  };
  EXPECT_EQ(tail(rows[0], 6), "0.25,0.5,0.75,,,0") << rows[0];  // no health recorded
  EXPECT_EQ(tail(rows[1], 6), "1.25,,1.75,2,7,0.01") << rows[1];  // l1 invalid
  EXPECT_EQ(tail(rows[2], 6), "2.25,2.5,2.75,0,3,0.02") << rows[2];

  const std::string h5 = dir_.file("health.h5");
  ASSERT_EQ(runs(fmt::format("export {} --h5 {}", id, shell_quote(h5))).code, 0);
  H5Handle f(H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(f.ok());
  H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", id).c_str(), H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(g.ok());
  size_t n = 0, cols = 0;
  const auto l = read<float>(g.get(), "l", H5T_NATIVE_FLOAT, n, cols);
  ASSERT_EQ(n, 4u);
  ASSERT_EQ(cols, 3u);
  EXPECT_TRUE(std::isnan(l[1 * 3 + 1]));
  EXPECT_EQ(l[1 * 3 + 0], 1.25f);
  EXPECT_EQ(l[2 * 3 + 1], 2.5f);
  const auto invalid = read<uint32_t>(g.get(), "l_invalid", H5T_NATIVE_UINT32, n, cols);
  EXPECT_EQ(invalid, (std::vector<uint32_t>{0, 2, 0, 0}));
  const auto age = read<float>(g.get(), "l_age_ms", H5T_NATIVE_FLOAT, n, cols);
  ASSERT_EQ(age.size(), 4u);
  EXPECT_TRUE(std::isnan(age[0]));
  EXPECT_EQ(age[1], 7.0f);
  EXPECT_EQ(age[2], 3.0f);
}

// A hasel identification run (3 outputs, 6 inputs, 18 sensors) at 130 Hz
// as a --sim-fast simulator records it: steps from 100, its clock the host's
// (34 us a step); sample 5 carries no step.
int64_t record_sim_fast_run(const std::string& db) {
  Recorder r(db);
  RunInfo ri;
  ri.platform = "hasel";
  ri.kind = "ident";
  ri.n = 3;
  ri.m = 6;
  ri.w = 18;
  ri.loop_rate_hz = 130;
  const int64_t id = r.begin_run(ri);
  for (uint32_t k = 0; k < 40; ++k) {
    Sample s;
    s.k = k;
    s.n = 3;
    s.m = 6;
    s.w = 18;
    s.mask = k == 5 ? uint8_t(tf::kTime | tf::kYTrue | tf::kU) : uint8_t(tf::kStep | tf::kTime | tf::kYTrue | tf::kU);
    s.step = 100 + k;
    s.time_us = 1000 + 34 * k;
    for (int i = 0; i < 18; ++i) s.l[i] = float(k) + 0.5f * float(i);
    r.add_sample(id, s);
  }
  r.end_run(id, "completed", 40, 0);
  r.flush();
  return id;
}

std::vector<std::string> dataset_strings(hid_t g, const char* dataset, const char* attr) {
  H5Handle d(H5Dopen2(g, dataset, H5P_DEFAULT), H5Dclose);
  if (!d.ok()) return {"<no dataset>"};
  return strings(d.get(), attr, false);
}

// What MATLAB's iddata needs: t steps by 1/loop_rate_hz, the very doubles
// (step - first step) / rate, not the host's clock the simulator sent.
TEST_F(H5Export, TIsTheStepTimeAndTheFirmwareClockIsKeptBeside) {
  const int64_t id = record_sim_fast_run(db());
  const std::string out = dir_.file("fast.h5");
  const auto r = runs(fmt::format("export {} --h5 {}", id, shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  H5Handle f(H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(f.ok());
  H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", id).c_str(), H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(g.ok());
  size_t rows = 0, cols = 0;
  const auto t = read<double>(g.get(), "t", H5T_NATIVE_DOUBLE, rows, cols);
  ASSERT_EQ(rows, 40u);
  EXPECT_EQ(cols, 0u);
  for (size_t k = 0; k < 40; ++k) {
    if (k == 5) EXPECT_TRUE(std::isnan(t[k])) << t[k];  // no step in the row
    else EXPECT_EQ(t[k], double(k) / 130.0) << k;
  }
  const auto t_fw = read<double>(g.get(), "t_firmware", H5T_NATIVE_DOUBLE, rows, cols);
  ASSERT_EQ(rows, 40u);
  for (size_t k = 0; k < 40; ++k) EXPECT_NEAR(t_fw[k], 34e-6 * double(k), 1e-12) << k;
  const auto us = read<uint32_t>(g.get(), "time_us", H5T_NATIVE_UINT32, rows, cols);
  ASSERT_EQ(rows, 40u);
  EXPECT_EQ(us[3], 1000u + 3 * 34);
  H5Handle td(H5Dopen2(g.get(), "t", H5P_DEFAULT), H5Dclose);
  EXPECT_EQ(string_attr(td.get(), "unit"), "s");
  EXPECT_EQ(number_attr<double>(g.get(), "loop_rate_hz", H5T_NATIVE_DOUBLE), 130.0);
}

// Each dataset's columns carry their names and units, as rigs/hasel.toml
// gives them, and the group names the outputs, inputs and sensors.
TEST_F(H5Export, AHaselRunsColumnsCarryTheRigFilesNamesAndUnits) {
  const int64_t id = record_sim_fast_run(db());
  const std::string out = dir_.file("named.h5");
  const auto r = runs(fmt::format("export {} --h5 {}", id, shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(contains(r.output, "without channel names")) << r.output;
  const Rig rig = load_rig_arg("hasel");  // the file the console reads ($NLSOFT_RIGS)
  std::vector<std::string> out_names, out_units, in_names, in_units, l_names, l_units;
  for (const auto& o : rig.outputs) out_names.push_back(o.name), out_units.push_back(o.unit);
  for (const auto& i : rig.inputs) in_names.push_back(i.name), in_units.push_back(i.unit);
  for (const auto& l : rig.sensors) l_names.push_back(l.name), l_units.push_back(l.unit);
  // Not vacuous: the file is the one these words describe.
  ASSERT_EQ(out_names, (std::vector<std::string>{"x", "y", "z"}));
  ASSERT_EQ(in_names.size(), 6u);
  EXPECT_EQ(in_names[0], "h1");
  ASSERT_EQ(l_names.size(), 18u);
  EXPECT_EQ(l_names[0], "b1x");
  EXPECT_EQ(l_units[0], "gauss");

  H5Handle f(H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(f.ok());
  H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", id).c_str(), H5P_DEFAULT), H5Gclose);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(strings(g.get(), "output_names", false), out_names);
  EXPECT_EQ(strings(g.get(), "input_names", false), in_names);
  EXPECT_EQ(strings(g.get(), "sensor_names", false), l_names);
  EXPECT_EQ(dataset_strings(g.get(), "y_true", "names"), out_names);
  EXPECT_EQ(dataset_strings(g.get(), "y_true", "units"), out_units);
  EXPECT_EQ(dataset_strings(g.get(), "u", "names"), in_names);
  EXPECT_EQ(dataset_strings(g.get(), "u", "units"), in_units);
  EXPECT_EQ(dataset_strings(g.get(), "l", "names"), l_names);
  EXPECT_EQ(dataset_strings(g.get(), "l", "units"), l_units);
  // Shared by every column: also the one word format 1 wrote.
  H5Handle y(H5Dopen2(g.get(), "y_true", H5P_DEFAULT), H5Dclose);
  EXPECT_EQ(string_attr(y.get(), "unit"), "mm");
  H5Handle l(H5Dopen2(g.get(), "l", H5P_DEFAULT), H5Dclose);
  EXPECT_EQ(string_attr(l.get(), "unit"), "gauss");
}

// A run of a rig the console does not know by name (a lab's own file) is
// exported without names, and one line says so and how to name them; --rig
// FILE names them. A shipped rig's name on a run of other sizes is the same.
TEST_F(H5Export, ARunOfAnUnknownRigIsExportedWithoutNamesAndSaysSo) {
  int64_t id = 0, other = 0;
  {
    Recorder rec(db());
    for (const char* platform : {"bench-arm", "hasel"}) {
      RunInfo ri;
      ri.platform = platform;
      ri.n = 1;
      ri.m = 1;
      ri.loop_rate_hz = 50;
      const int64_t run = rec.begin_run(ri);
      for (uint32_t k = 0; k < 5; ++k) {
        Sample s;
        s.k = k;
        s.n = 1;
        s.m = 1;
        s.mask = uint8_t(tf::kStep | tf::kYTrue | tf::kU);
        s.step = k;
        s.y_true()[0] = float(k);
        s.u()[0] = -float(k);
        rec.add_sample(run, s);
      }
      rec.end_run(run, "completed", 5, 0);
      (std::string(platform) == "hasel" ? other : id) = run;
    }
    rec.flush();
  }
  const std::string out = dir_.file("unnamed.h5");
  auto r = runs(fmt::format("export {} --h5 {}", id, shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, fmt::format("exported without channel names and units: run {}'s rig \"bench-arm\" "
                                             "is in no rigs folder (--rig FILE names them)\n",
                                             id)))
      << r.output;
  {
    H5Handle f(H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    ASSERT_TRUE(f.ok());
    H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", id).c_str(), H5P_DEFAULT), H5Gclose);
    ASSERT_TRUE(g.ok());
    EXPECT_FALSE(H5Aexists(g.get(), "output_names") > 0);
    H5Handle y(H5Dopen2(g.get(), "y_true", H5P_DEFAULT), H5Dclose);
    ASSERT_TRUE(y.ok());
    EXPECT_FALSE(H5Aexists(y.get(), "names") > 0);
    size_t rows = 0, cols = 0;
    EXPECT_EQ(read<double>(g.get(), "t", H5T_NATIVE_DOUBLE, rows, cols)[4], 4.0 / 50.0);
  }
  // The shipped rig's name on a run of other sizes: no names, said.
  r = runs(fmt::format("export {} --h5 {}", other, shell_quote(dir_.file("other.h5"))));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, fmt::format("run {} has n=1 m=1 w=0, the shipped rig hasel n=3 m=6 w=18", other)))
      << r.output;

  // The lab's file, by path: a copy of msd's (one output x in m, one input u in N/kg).
  const std::string lab = dir_.file("bench-arm.toml");
  {
    std::ifstream from(rig_path("msd"));
    std::ofstream to(lab);
    to << from.rdbuf();
  }
  const std::string named = dir_.file("named.h5");
  r = runs(fmt::format("export {} {} --h5 {} --rig {}", id, other, shell_quote(named), shell_quote(lab)));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(contains(r.output, "without channel names")) << r.output;
  H5Handle f(H5Fopen(named.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(f.ok());
  for (int64_t run : {id, other}) {
    H5Handle g(H5Gopen2(f.get(), fmt::format("run_{}", run).c_str(), H5P_DEFAULT), H5Gclose);
    ASSERT_TRUE(g.ok());
    EXPECT_EQ(strings(g.get(), "output_names", false), std::vector<std::string>{"x"});
    EXPECT_EQ(dataset_strings(g.get(), "y_true", "units"), std::vector<std::string>{"m"});
    EXPECT_EQ(dataset_strings(g.get(), "u", "names"), std::vector<std::string>{"u"});
    EXPECT_EQ(dataset_strings(g.get(), "u", "units"), std::vector<std::string>{"N/kg"});
  }
}

// --rig names a rig whose sizes are not the run's: refused, naming both,
// with nothing written; and a CSV takes no --rig (its columns keep their names).
TEST_F(H5Export, ARigOfOtherSizesThanTheRunsIsRefusedNamingBoth) {
  std::vector<Sample> a;
  const int64_t id = record_run(db(), true, a);  // hasel: n=3 m=6 w=0
  const std::string out = dir_.file("refused.h5");
  auto r = runs(fmt::format("export {} --h5 {} --rig msd", id, shell_quote(out)));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, fmt::format("runs export --rig msd: the rig msd has n=1 m=1 w=0, run {} (rig "
                                             "\"hasel\") has n=3 m=6 w=0",
                                             id)))
      << r.output;
  EXPECT_FALSE(exists(out));
  const int64_t ident = record_sim_fast_run(db());  // hasel with its 18 sensors; tendon has 11
  r = runs(fmt::format("export {} --h5 {} --rig tendon", ident, shell_quote(out)));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "the rig tendon has n=3 m=2 w=11")) << r.output;
  EXPECT_FALSE(exists(out));
  r = runs(fmt::format("export {} --h5 {} --rig {}", id, shell_quote(out), shell_quote(dir_.file("none.toml"))));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "none.toml")) << r.output;
  EXPECT_FALSE(exists(out));
  const std::string csv = dir_.file("refused.csv");
  r = runs(fmt::format("export {} --csv {} --rig hasel", id, shell_quote(csv)));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "go into HDF5")) << r.output;
  EXPECT_FALSE(exists(csv));
}

TEST_F(H5Export, SeveralRunsInOneCsvCarryARunColumn) {
  std::vector<Sample> a, b;
  const int64_t ida = record_run(db(), true, a);
  const int64_t idb = record_run(db(), true, b);
  const std::string out = dir_.file("both.csv");
  const auto r = runs(fmt::format("export {} {} --csv {}", idb, ida, shell_quote(out)));
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(out);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line.rfind("run,k,step,time_us,", 0), 0u) << line;
  std::map<std::string, int> per_run;
  while (std::getline(in, line)) ++per_run[line.substr(0, line.find(','))];
  EXPECT_EQ(per_run[std::to_string(ida)], 100);
  EXPECT_EQ(per_run[std::to_string(idb)], 100);
  EXPECT_EQ(per_run.size(), 2u);
}

// Nothing is written for a request that cannot be met, and each says why.
TEST_F(H5Export, BadRequestsAreClearErrorsAndWriteNothing) {
  std::vector<Sample> a;
  const int64_t id = record_run(db(), true, a);
  const std::string out = dir_.file("x.h5");
  auto r = runs(fmt::format("export {} 99 --h5 {}", id, shell_quote(out)));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "no run 99")) << r.output;
  EXPECT_FALSE(exists(out));
  r = runs(fmt::format("export {} {} --h5 {}", id, id, shell_quote(out)));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "named twice")) << r.output;
  EXPECT_FALSE(exists(out));
  r = runs(fmt::format("export {} --h5 {} --csv {}", id, shell_quote(out), shell_quote(dir_.file("x.csv"))));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "not both")) << r.output;
  EXPECT_FALSE(exists(out));
  r = runs(fmt::format("export {} --h5 {}", id, shell_quote(dir_.path)));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, dir_.path)) << r.output;
  // A run of another shape does not share a CSV header with it.
  {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "tendon";
    ri.n = 2;
    ri.m = 2;
    const int64_t other = rec.begin_run(ri);
    rec.end_run(other, "completed", 0, 0);
    rec.flush();
    r = runs(fmt::format("export {} {} --csv {}", id, other, shell_quote(dir_.file("mixed.csv"))));
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "one CSV holds runs of one shape")) << r.output;
    EXPECT_FALSE(exists(dir_.file("mixed.csv")));
  }
}

}  // namespace
}  // namespace nlsoft::console
