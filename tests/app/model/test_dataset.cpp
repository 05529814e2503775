// Preprocessing (the paper's eq. 14), normalisation, split, CSV and excitation.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <sstream>

#include "app/model/dataset.hpp"
#include "app/model/error.hpp"
#include "app/model/excitation.hpp"
#include "app/model/recorded_run.hpp"
#include "shared/sim_plant.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
using namespace nlsoft::model;

namespace {

// u_i(k) = 100 k + 10 i, y_j(k) = 1000 k + j + 0.5, l_i(k) = -k - 0.01 i:
// every value names its signal and time, so a misplaced column shows.
Series tiny(long q, int m, int n, int w) {
  Series s;
  s.resize(q, m, n, w);
  for (long k = 0; k < q; ++k) {
    s.time(k) = 0.1 * double(k);
    for (int i = 0; i < m; ++i) s.u(k, i) = 100.0 * double(k) + 10.0 * i;
    for (int j = 0; j < n; ++j) s.y(k, j) = 1000.0 * double(k) + j + 0.5;
    for (int i = 0; i < w; ++i) s.l(k, i) = -double(k) - 0.01 * i;
  }
  return s;
}

}  // namespace

TEST(Dataset, RowsFollowTheControllerInputLayout) {
  const Series s = tiny(6, 2, 1, 1);
  const Dataset d = build_dataset(s, 2, 2);
  ASSERT_EQ(d.rows(), 6 - 2);  // q - max(nd, dd)
  ASSERT_EQ(d.X.cols(), 2 * 2 + 2 * 1 + 1);
  for (long r = 0; r < d.rows(); ++r) {
    const double k = double(r + 1);
    const std::vector<double> expect = {100 * k,        100 * k + 10,        // u(k)
                                        100 * (k - 1),  100 * (k - 1) + 10,  // u(k-1)
                                        1000 * k + 0.5, 1000 * (k - 1) + 0.5,  // y(k), y(k-1)
                                        -k};                                  // l(k)
    for (size_t c = 0; c < expect.size(); ++c) EXPECT_DOUBLE_EQ(d.X(r, long(c)), expect[c]) << "row " << r << " col " << c;
    EXPECT_DOUBLE_EQ(d.Y(r, 0), 1000 * (k + 1) + 0.5);  // label y(k+1)
  }
}

TEST(Dataset, LongerInputHistory) {
  const Series s = tiny(7, 1, 2, 0);
  const Dataset d = build_dataset(s, 3, 2);
  ASSERT_EQ(d.rows(), 7 - 3);
  EXPECT_EQ(d.first_k, 2);
  // row 0 is k = 2: u(2) u(1) u(0) | y0(2) y1(2) y0(1) y1(1)
  const std::vector<double> expect = {200, 100, 0, 2000.5, 2001.5, 1000.5, 1001.5};
  for (size_t c = 0; c < expect.size(); ++c) EXPECT_DOUBLE_EQ(d.X(0, long(c)), expect[c]);
  EXPECT_DOUBLE_EQ(d.Y(0, 1), 3001.5);
  EXPECT_THROW(build_dataset(tiny(3, 1, 1, 0), 3, 3), PipelineError);
}

TEST(Dataset, NoLabelLeak) {
  const Series s = generate_excitation(PlantKind::Tendon, 2000, 3);
  const Dataset d = build_dataset(s, 2, 2);
  const InputLayout& L = d.layout;
  for (int j = 0; j < L.n; ++j) {
    for (int c = 0; c < L.p(); ++c) EXPECT_FALSE(d.X.col(c).isApprox(d.Y.col(j))) << "label y" << j << " in column " << c;
    // the label of row r is the newest y of row r + 1, and only there
    for (long r = 0; r + 1 < d.rows(); ++r) ASSERT_EQ(d.Y(r, j), d.X(r + 1, L.y_begin() + j));
  }
}

TEST(Dataset, NormalisationRange) {
  const Series s = generate_excitation(PlantKind::Hasel, 5000, 2);
  const Dataset d = build_dataset(s, 2, 2);
  const Partition P = partition(d.rows());
  NormalisationSpec spec;
  spec.u_lo.assign(6, 0.0);
  spec.u_hi.assign(6, 1.0);
  spec.y_neutral = {0.0, 0.0, 9.6};
  const Normalisation nz = fit_normalisation(d, P.train_end, spec);
  const Eigen::MatrixXd Xn = normalise_inputs(nz, d.X.topRows(P.train_end));
  EXPECT_GE(Xn.minCoeff(), -0.5 - 1e-9);
  EXPECT_LE(Xn.maxCoeff(), 0.5 + 1e-9);
  for (int c = 0; c < d.layout.p(); ++c) {  // every column uses its whole range
    EXPECT_NEAR(Xn.col(c).maxCoeff() - Xn.col(c).minCoeff(), 1.0, 0.05) << "column " << c;
  }
  // u maps the actuator limits, not just the data, to +-0.5
  EXPECT_DOUBLE_EQ(nz.in_offset(0), 0.5);
  EXPECT_DOUBLE_EQ(nz.in_scale(0), 1.0);
  // outputs: centred at the neutral point, the largest deviation at 1/margin
  for (int j = 0; j < 3; ++j) {
    EXPECT_DOUBLE_EQ(nz.out_offset(j), spec.y_neutral[size_t(j)]);
    const double t = ((d.Y.col(j).topRows(P.train_end).array() - nz.out_offset(j)) / nz.out_scale(j)).abs().maxCoeff();
    EXPECT_NEAR(t, 1.0 / spec.out_margin, 1e-12);
  }
}

TEST(Dataset, TimeSeriesSplitMatchesSklearn) {
  // sklearn TimeSeriesSplit(10) on 110 rows: test chunks of 10 from row 10
  const std::vector<Fold> f = time_series_split(110, 10);
  ASSERT_EQ(f.size(), 10u);
  for (size_t i = 0; i < f.size(); ++i) {
    EXPECT_EQ(f[i].test_begin, 10 + 10 * long(i));
    EXPECT_EQ(f[i].test_end, 20 + 10 * long(i));
  }
  // 1005 rows: chunk 91, the remainder goes to the first training block
  const Partition p = partition(1005);
  EXPECT_EQ(p.test_end, 1005);
  EXPECT_EQ(p.test_end - p.test_begin, 91);
  EXPECT_EQ(p.val_end, p.test_begin);
  EXPECT_EQ(p.val_end - p.val_begin, 91);
  EXPECT_EQ(p.train_end, p.val_begin);
  EXPECT_EQ(p.train_end, 1005 - 2 * 91);
  EXPECT_THROW(time_series_split(10, 10), PipelineError);
}

TEST(SeriesCsv, RoundTripAndErrors) {
  const Series s = generate_excitation(PlantKind::Tendon, 300, 5);
  std::stringstream ss;
  write_series_csv(ss, s);
  std::string header;
  std::getline(std::stringstream(ss.str()), header);
  EXPECT_EQ(header, "time,u0,u1,y0,y1,y2,l0,l1,l2,l3,l4,l5,l6,l7,l8,l9,l10");
  const Series r = parse_series_csv(ss, "mem");
  ASSERT_EQ(r.rows(), s.rows());
  EXPECT_EQ(r.w, 11);
  EXPECT_TRUE(r.y.isApprox(s.y, 1e-7));

  auto fails = [](const std::string& text, const std::string& what) {
    std::stringstream in(text);
    try {
      parse_series_csv(in, "bad.csv");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const PipelineError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  fails("time,u0,y0\n0,1,2\n0.1,x,3\n", "bad.csv:3: column 2 ('u0'): not a number");
  fails("time,u0,y0\n0,1,2\n0.1,2\n", "expected 3 values");
  fails("time,u0,y0\n0,1,2\n0,1,2\n", "bad.csv:3: time 0 s does not follow the previous row's 0 s: time must increase");
  fails("t,u0,y0\n0,1,2\n", "must start with 'time'");
  fails("time,u0,z0\n0,1,2\n", "at least one u column and one y column");
  fails("time,u0,y0,q\n0,1,2,3\n", "unexpected column 'q'");
  fails("time,u0,y0\n0,1,nan\n", "not a finite number");
  fails("time,u0,y0\n", "no data rows");
}

TEST(Excitation, DeterministicInsideLimitsAndCoversTheTaskSpace) {
  const Series a = generate_excitation(PlantKind::Hasel, 20000, 7);
  const Series b = generate_excitation(PlantKind::Hasel, 20000, 7);
  const Series c = generate_excitation(PlantKind::Hasel, 20000, 8);
  EXPECT_TRUE(a.u == b.u && a.l == b.l);
  EXPECT_FALSE(a.u == c.u);
  EXPECT_GE(a.u.minCoeff(), 0.0);
  EXPECT_LE(a.u.maxCoeff(), 1.0);
  // the platform height covers most of its 0..19.2 mm stroke, tilts both ways
  EXPECT_LT(a.y.col(2).minCoeff(), 3.0);
  EXPECT_GT(a.y.col(2).maxCoeff(), 16.0);
  EXPECT_LT(a.y.col(0).minCoeff(), -6.0);
  EXPECT_GT(a.y.col(0).maxCoeff(), 6.0);

  const Series m = generate_excitation(PlantKind::Msd, 50000, 1);
  EXPECT_LE(m.u.cwiseAbs().maxCoeff(), 2000.0);
  EXPECT_THROW(generate_excitation(PlantKind::Msd, 10, 1), PipelineError);
}

// What no plant can run is refused by name, never stood in for: the
// generic plant without its spec, a kind the registry has no row for, and a
// generic spec the plant refuses (it once fell back to the outputs' middle).
TEST(Excitation, RefusesAPlantThatCannotRun) {
  auto says = [](const std::function<void()>& f, const std::string& words) {
    try {
      f();
      ADD_FAILURE() << "not refused: " << words;
    } catch (const PipelineError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  says([] { generate_excitation(PlantKind::Generic, 1000, 1); }, "is no hand-written plant");
  says([] { generate_excitation(static_cast<PlantKind>(9), 1000, 1); }, "is no hand-written plant");
  PlantTarget t;
  t.name = "bent";
  t.n = 1;
  t.y_rest = {0.5};
  t.plant = TargetPlant::Generic;
  t.generic.m = 0;  // no input: generic_spec_problem refuses it
  double y[1] = {};
  says([&] { neutral_output(t, y); }, "rig 'bent': its generic plant cannot run");
  says([&] { generate_excitation(t, 1000, 1); }, "rig 'bent': its generic plant cannot run");
}

// A gap in a recorded run cuts it: each stretch gives its own rows and no
// history window reaches across the gap.
TEST(Dataset, AGapCutsTheSeriesAndNoWindowSpansIt) {
  Series s = tiny(10, 1, 1, 0);
  s.breaks = {5};
  const Dataset d = build_dataset(s, 2, 2);
  ASSERT_EQ(d.rows(), (5 - 2) + (5 - 2));
  ASSERT_EQ(d.pieces.size(), 2u);
  EXPECT_EQ(d.pieces[0].begin, 0);
  EXPECT_EQ(d.pieces[0].end, 3);
  EXPECT_EQ(d.pieces[1].begin, 3);
  EXPECT_EQ(d.pieces[1].end, 6);
  const InputLayout& L = d.layout;
  for (long r = 0; r < d.rows(); ++r) {
    // y(k), y(k-1) and the label y(k+1) are consecutive samples of one stretch.
    EXPECT_DOUBLE_EQ(d.X(r, L.y_begin()) - d.X(r, L.y_begin() + 1), 1000.0) << "row " << r;
    EXPECT_DOUBLE_EQ(d.Y(r, 0) - d.X(r, L.y_begin()), 1000.0) << "row " << r;
    const double k = (d.X(r, L.y_begin()) - 0.5) / 1000.0;
    EXPECT_FALSE(k == 4.0 || k == 5.0) << "row " << r << " has a window across the gap";
  }
  s.breaks = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  EXPECT_THROW(build_dataset(s, 2, 2), PipelineError);
}

// Runs stacked into one dataset: the rows copied where asked, and the
// pieces cut to the copied range and shifted with it, so no free run of the
// stacked set crosses from one run into the next or through a run's gap.
TEST(Dataset, CopyRowsStacksRowsWithTheirPiecesShifted) {
  Series s = tiny(10, 1, 1, 0);
  s.breaks = {5};
  const Dataset from = build_dataset(s, 2, 2);  // pieces [0, 3) and [3, 6)
  Dataset into;
  into.layout = from.layout;
  into.X.setZero(2 + 4, from.X.cols());
  into.Y.setZero(2 + 4, from.Y.cols());
  into.pieces.push_back({0, 2});  // an earlier run's rows
  const std::vector<RowRange> added = copy_rows(into, 2, from, 1, 5);
  ASSERT_EQ(added.size(), 2u);
  EXPECT_EQ(added[0].begin, 2);
  EXPECT_EQ(added[0].end, 4);  // from's rows 1, 2
  EXPECT_EQ(added[1].begin, 4);
  EXPECT_EQ(added[1].end, 6);  // from's rows 3, 4
  ASSERT_EQ(into.pieces.size(), 3u);
  EXPECT_EQ(into.pieces[0].end, 2);
  for (long r = 0; r < 4; ++r) {
    EXPECT_EQ(into.X.row(2 + r), from.X.row(1 + r)) << "row " << r;
    EXPECT_EQ(into.Y.row(2 + r), from.Y.row(1 + r)) << "row " << r;
  }
  EXPECT_TRUE(into.X.topRows(2).isZero());
  EXPECT_TRUE(copy_rows(into, 6, from, 3, 3).empty());  // an empty range copies nothing
}

// A recorded run's samples become the series: a jump of the firmware's
// step count is a gap, and a sample lacking the measured output is left
// out with a gap in its place.
TEST(RecordedRun, StepJumpsAndIncompleteSamplesBreakTheSeries) {
  RecordedRun r;
  r.name = "run 7";
  r.rig = "msd";
  r.m = r.n = 1;
  const int64_t steps[] = {10, 11, 12, 14, 15, 16, 17, 18};
  for (int i = 0; i < 8; ++i) {
    r.k.push_back(i);
    r.step.push_back(steps[i]);
    r.time_us.push_back(1000 * steps[i]);
    r.u.push_back(double(i));
    r.y.push_back(i == 5 ? std::nan("") : 0.1 * i);
  }
  const PlantTarget t = test::shipped_target("msd");
  const Series s = recorded_series(r, t);
  ASSERT_EQ(s.rows(), 7);
  EXPECT_EQ(s.breaks, (std::vector<long>{3, 5}));
  EXPECT_DOUBLE_EQ(s.time(0), 0.0);
  EXPECT_NEAR(s.time(3), 0.004, 1e-12);  // the firmware's clock, across the gap
  EXPECT_DOUBLE_EQ(s.u(5, 0), 6.0);

  RecordedRun other = r;
  other.rig = "hasel";
  EXPECT_THROW(recorded_series(other, t), PipelineError);
  RecordedRun unmeasured = r;
  for (double& y : unmeasured.y) y = std::nan("");
  EXPECT_THROW(recorded_series(unmeasured, t), PipelineError);
  // Telemetry decimated by 4: no sample follows another by one step.
  RecordedRun decimated = r;
  for (size_t i = 0; i < decimated.step.size(); ++i) decimated.step[i] = int64_t(4 * i), decimated.y[i] = 0.1;
  try {
    recorded_series(decimated, t);
    ADD_FAILURE() << "a decimated run was taken";
  } catch (const PipelineError& e) {
    EXPECT_NE(std::string(e.what()).find("run 7: no two samples are one control step apart (the first two are 4 "
                                         "control steps apart"),
              std::string::npos)
        << e.what();
  }
}
