// `runs export ... --h5`: runs written by the recorder come back from the
// file through HDF5's own reader, dataset by dataset and attribute by
// attribute; gaps and fields the firmware never sent stay visible; several
// runs in one CSV carry a run column; bad requests write nothing.
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
#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

namespace tf = protocol::telemetry_field;
using test::run_process;
using test::shell_quote;

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }
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
  EXPECT_EQ(number_attr<int32_t>(f.get(), "format_version", H5T_NATIVE_INT32), 1);

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
  // The 32-bit microsecond clock wrapped at sample 60: t goes on rising.
  for (size_t i = 0; i < 100; ++i) EXPECT_NEAR(t[i], 0.01 * double(i), 1e-9) << i;
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
  EXPECT_EQ(line.substr(line.size() - std::string(",l0,l1,l2,l_invalid,l_age_ms").size()), ",l0,l1,l2,l_invalid,l_age_ms")
      << line;
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);
  auto tail = [](const std::string& row, int cells) {
    size_t at = row.size();
    for (int i = 0; i < cells; ++i) at = row.rfind(',', at - 1);
    return row.substr(at + 1);
  };
  EXPECT_EQ(tail(rows[0], 5), "0.25,0.5,0.75,,") << rows[0];  // no health recorded
  EXPECT_EQ(tail(rows[1], 5), "1.25,,1.75,2,7") << rows[1];   // l1 invalid
  EXPECT_EQ(tail(rows[2], 5), "2.25,2.5,2.75,0,3") << rows[2];

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
