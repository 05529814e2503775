// Files from anyone read by the model pipeline: a CSV header cell quoted in
// an error is shown escaped, and a model file whose normalisation no
// training makes (3e38: the controller sees nothing move) is refused when
// loaded, with the value named.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "app/model/csv.hpp"
#include "app/model/error.hpp"
#include "app/model/model_store.hpp"
#include "app/model/atomic_file.hpp"

using namespace nlsoft;
using namespace nlsoft::model;

namespace {

std::string error_of(const std::string& csv) {
  std::istringstream in(csv);
  try {
    parse_csv(in, "bad.csv", true);
  } catch (const PipelineError& e) {
    return e.what();
  }
  return "";
}

bool has_raw_control(const std::string& s) {
  for (size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) return true;
    if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) <= 0x9f) return true;  // C1
    if (s.compare(i, 3, "\xe2\x80\xae") == 0) return true;                                           // U+202E
  }
  return false;
}

// The header is the file's: its cell goes into the message of a bad cell
// below it, and was quoted raw (an ESC [2J cleared the screen).
TEST(ModelTrust, AHeaderCellQuotedInAnErrorIsEscaped) {
  const std::string e = error_of("time,u\x1b[2J\xc2\x9b" "0\xe2\x80\xae,y0\n0,x,3\n");
  ASSERT_NE(e.find("bad.csv:2: column 2 ("), std::string::npos) << e;
  EXPECT_NE(e.find("not a number: 'x'"), std::string::npos) << e;
  EXPECT_FALSE(has_raw_control(e)) << e;
  EXPECT_NE(e.find("\\x1b[2J"), std::string::npos) << e;
}

std::string shipped_model() { return std::string(NLSOFT_SOURCE_DIR) + "/app/models/msd.nlsm"; }

// msd's model with one normalisation value changed, written where a user
// would give it.
std::string model_with(size_t index, float value) {
  ModelFile f = load_model_file(shipped_model());
  f.params.at(index) = value;
  const std::string path = ::testing::TempDir() + "/crafted.nlsm";
  save_model_file(path, f);
  return path;
}

std::string load_error(const std::string& path) {
  try {
    load_model_file(path);
  } catch (const PipelineError& e) {
    return e.what();
  }
  return "";
}

TEST(ModelTrust, AnImplausibleNormalisationIsRefusedOnLoad) {
  const ModelFile f = load_model_file(shipped_model());
  const Model<HostCapacity> m = f.view();
  const size_t p = size_t(m.p());
  // in_scale[0], out_scale[0] at 3e38; out_offset[0] at 1e30; in_scale[0] at 0.
  struct Case {
    size_t index;
    float value;
    const char* named;
  };
  for (const Case c : {Case{p, 3e38f, "in_scale[0] = 3e+38"}, Case{2 * p + m.n, 3e38f, "out_scale[0] = 3e+38"},
                       Case{2 * p, 1e30f, "out_offset[0] = 1e+30"}, Case{p, 0.0f, "in_scale[0] = 0"},
                       Case{p, 1e-30f, "in_scale[0] = 1e-30"}}) {
    const std::string e = load_error(model_with(c.index, c.value));
    EXPECT_NE(e.find("is not a plausible model: its normalisation " + std::string(c.named)), std::string::npos)
        << c.named << ": " << e;
  }
  // What training makes loads (the shipped ones, and a scale of 1e12: a
  // signal spanning a picometre).
  EXPECT_EQ(load_error(model_with(p, 1e12f)), "");
  for (const char* name : {"msd", "hasel", "tendon"})
    EXPECT_EQ(load_error(std::string(NLSOFT_SOURCE_DIR) + "/app/models/" + name + ".nlsm"), "") << name;
}

}  // namespace
