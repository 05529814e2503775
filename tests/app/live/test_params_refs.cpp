// Parameter values and references from text: clear errors, nothing half-set.
#include <gtest/gtest.h>

#include <fstream>

#include "host/files/cli_error.hpp"
#include "app/link/param_catalog.hpp"
#include "app/live/reference_spec.hpp"
#include "app/live/reference_table.hpp"
#include "host/rig/rig.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::load_rig;

namespace {

ParamInfo param(const char* name, protocol::ParamType type, uint8_t size) {
  ParamInfo p;
  p.name = name;
  p.type = type;
  p.size = size;
  p.min = 0;
  p.max = 100;
  return p;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const CliError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamValues, ParsesBlankOrCommaSeparated) {
  const ParamInfo q = param("Q", protocol::ParamType::F32, 3);
  EXPECT_EQ(parse_param_values(q, {"1e6", "2e6", "1e6"}), (std::vector<double>{1e6, 2e6, 1e6}));
  EXPECT_EQ(parse_param_values(q, {"1e6,2e6,1e6"}), (std::vector<double>{1e6, 2e6, 1e6}));
  EXPECT_EQ(format_param_values(q, {1e6, 2e6, 0.5}), "1e+06 2e+06 0.5");
  uint32_t words[3];
  encode_param_values(q, {1.5, 2, 3}, words);
  EXPECT_EQ(decode_param_values(q, words, 3), (std::vector<double>{1.5, 2, 3}));
}

// What is shown and saved reads back as the very float the firmware holds
// (a saved set loads without a spurious change), in six digits where they do.
TEST(ParamValues, FormattedFloatsReadBackExactly) {
  const ParamInfo eps = param("eps", protocol::ParamType::F32, 1);
  for (float v : {1.0f / 130.0f, 1.0f / 120.0f, 1e-25f, 0.1f, 3.14159274f, 123456.789f, -2e-7f}) {
    const std::string text = format_param_values(eps, {double(v)});
    EXPECT_EQ(float(parse_param_values(eps, {text})[0]), v) << text;
  }
  EXPECT_EQ(format_param_values(eps, {double(1.0f / 130.0f)}), "0.0076923077");
  EXPECT_EQ(format_param_values(eps, {1e-25}), "1e-25");
}

TEST(ParamValues, RefusesBadTextInWords) {
  const ParamInfo q = param("Q", protocol::ParamType::F32, 3);
  const ParamInfo n = param("N", protocol::ParamType::U8, 1);
  EXPECT_EQ(error_of([&] { parse_param_values(q, {"1", "2"}); }), "Q takes 3 values, got 2");
  EXPECT_EQ(error_of([&] { parse_param_values(q, {"1", "x", "2"}); }), "Q: 'x' is not a number");
  EXPECT_EQ(error_of([&] { parse_param_values(q, {"1", "nan", "2"}); }), "Q: 'nan' is not a finite number");
  EXPECT_EQ(error_of([&] { parse_param_values(n, {"2.5"}); }), "N: '2.5' must be a whole number >= 0");
  EXPECT_EQ(error_of([&] { parse_param_values(q, {"1,,2"}); }), "Q: empty value in '1,,2'");
}

// 1e40 is a finite double but no float32: it is refused as an overflow,
// with the limit, before anything is sent (the firmware would see infinity).
TEST(ParamValues, AValueBeyondFloat32IsAnOverflowWithTheLimit) {
  const ParamInfo q = param("Q", protocol::ParamType::F32, 3);
  EXPECT_EQ(error_of([&] { parse_param_values(q, {"1e40", "1", "1"}); }),
            "Q: '1e40' overflows a float32 (the firmware's number type): its magnitude must be at most 3.40282e+38");
  EXPECT_EQ(error_of([&] { parse_param_values(q, {"1", "-1e39", "1"}); }).find("'-1e39' overflows a float32"), 3u);
  EXPECT_EQ(parse_param_values(q, {"3.4e38", "1", "1"}).front(), 3.4e38) << "the largest floats still go through";
}

// PARAM_DESC gives the horizons the table's bound, 255 for every build; the
// build's capacity (INFO's max_n, max_nc) is what it really takes.
TEST(ParamCatalog, TheHorizonsRangeIsTheBuildsCapacity) {
  std::vector<ParamInfo> list = {param("N", protocol::ParamType::U8, 1), param("N1", protocol::ParamType::U8, 1),
                                 param("Nc", protocol::ParamType::U8, 1), param("Q", protocol::ParamType::F32, 3)};
  for (ParamInfo& p : list) p.min = 1, p.max = p.name == "Q" ? 1e12f : 255;
  apply_capacity(list, 12, 6);
  EXPECT_EQ(list[0].max, 12);
  EXPECT_EQ(list[0].capacity, "max_n");
  EXPECT_EQ(list[1].max, 12);
  EXPECT_EQ(list[2].max, 6);
  EXPECT_EQ(list[2].capacity, "max_nc");
  EXPECT_EQ(list[3].max, 1e12f);
  EXPECT_EQ(list[3].capacity, "");
  protocol::Nack nack;
  nack.request_type = uint8_t(protocol::MsgType::ParamSet);
  nack.status = uint8_t(protocol::StatusCode::TooLarge);
  EXPECT_EQ(describe_param_refusal(list[0], nack, {255}),
            "N = 255 is over this firmware build's capacity: at most 12 (max_n in INFO)");
}

TEST(ParamCatalog, FindsByNameAndListsTheKnownOnes) {
  ParamCatalog cat({param("Q", protocol::ParamType::F32, 3), param("Lambda", protocol::ParamType::F32, 6)});
  EXPECT_EQ(cat.find("lambda")->name, "Lambda");
  EXPECT_EQ(cat.find("R"), nullptr);
  EXPECT_EQ(error_of([&] { cat.require("R"); }), "unknown parameter 'R'; the firmware has: Q, Lambda");
}

const Rig& shipped(const char* name) {
  static const Rig hasel = load_rig(NLSOFT_RIGS_DIR "/hasel.toml"), tendon = load_rig(NLSOFT_RIGS_DIR "/tendon.toml"),
                   msd = load_rig(NLSOFT_RIGS_DIR "/msd.toml");
  return std::string(name) == "hasel" ? hasel : (std::string(name) == "tendon" ? tendon : msd);
}

TEST(ReferenceSpec, PresetWithOverrides) {
  const RefParams r = reference_from_spec(shipped("tendon"), 120.0, "infinity", {{"period", "4"}, {"a", "2"}});
  EXPECT_EQ(r.kind, RefKind::Infinity);
  EXPECT_FLOAT_EQ(r.A, 2.0f);
  EXPECT_NEAR(r.omega, 2 * 3.14159265 / 480.0, 1e-7);
  EXPECT_EQ(reference_key_value(r, 120.0, "period"), "4");
  const RefParams s = reference_from_spec(shipped("msd"), 1000.0, "step", {{"levels", "0.5,1"}, {"hold", "200"}});
  EXPECT_EQ(s.kind, RefKind::Step);
  EXPECT_EQ(s.level_count, 2);
  EXPECT_EQ(s.hold, 200);
}

TEST(ReferenceSpec, RefusesUnknownNamesKeysAndValues) {
  EXPECT_NE(error_of([] { reference_from_spec(shipped("hasel"), 130, "circle", {}); }).find("unknown reference 'circle'"),
            std::string::npos);
  EXPECT_EQ(error_of([] { reference_from_spec(shipped("hasel"), 130, "swirl", {{"radius", "2"}}); }),
            "unknown reference key 'radius'; known: a b c c0 c1 c2 omega lambda period scale hold levels");
  EXPECT_EQ(error_of([] { reference_from_spec(shipped("hasel"), 130, "swirl", {{"hold", "0"}}); }),
            "hold=0: must be a whole number of control steps, 1..65535");
  EXPECT_EQ(error_of([] { reference_from_spec(shipped("hasel"), 130, "pringle", {{"lambda", "-5"}}); }),
            "ref pringle: lambda must be > 0");
  EXPECT_EQ(error_of([] { reference_from_spec(shipped("hasel"), 130, "steps", {{"levels", "1,2,3,4"}}); }),
            "levels=1,2,3,4: at most 3 levels");
}

TEST(ReferenceTable, ReadsCsvWithHeaderAndComments) {
  test::TempDir dir;
  const std::string path = dir.file("t.csv");
  std::ofstream(path) << "# my path\nx,y,z\n1,2,3\n 4 , 5 , 6 \n\n";
  const ReferenceTablePoints t = read_reference_csv(path, 3);
  EXPECT_EQ(t.count(), 2u);
  EXPECT_EQ(t.rows, (std::vector<float>{1, 2, 3, 4, 5, 6}));
  const auto obj = reference_table_object(t);
  ASSERT_EQ(obj.size(), 8u + 24u);
  EXPECT_EQ(obj[0], 1);
  EXPECT_EQ(obj[1], 3);
  EXPECT_EQ(obj[4], 2);  // count, little-endian
}

TEST(ReferenceTable, RefusesMalformedCsvWithLineNumbers) {
  test::TempDir dir;
  const std::string path = dir.file("bad.csv");
  std::ofstream(path) << "x,y,z\n1,2,3\n1,2\n";
  EXPECT_EQ(error_of([&] { read_reference_csv(path, 3); }),
            path + ":3: 2 values on this row, the firmware wants 3 per point");
  std::ofstream(path) << "1,2,3\n1,zz,3\n";
  EXPECT_EQ(error_of([&] { read_reference_csv(path, 3); }), path + ":2: 'zz' is not a number");
  std::ofstream(path) << "1,2,inf\n";
  EXPECT_EQ(error_of([&] { read_reference_csv(path, 3); }), path + ":1: 'inf' is not a finite number");
  std::ofstream(path) << "# nothing\n";
  EXPECT_EQ(error_of([&] { read_reference_csv(path, 3); }), path + ": no points");
}

TEST(ReferenceTable, SwirlTableFollowsTheSharedPath) {
  const float centre[3] = {1, 2, 3};
  const ReferenceTablePoints t = swirl_table(centre, 2.0f, 3);
  EXPECT_EQ(t.count(), size_t(swirl::kPoints));
  EXPECT_FLOAT_EQ(t.rows[0], 1.0f);
  float p[3];
  swirl_point(700, p);
  EXPECT_FLOAT_EQ(t.rows[700 * 3 + 2], 3.0f + 2.0f * p[2]);
}

}  // namespace
}  // namespace nlsoft::console
