// Generated headers (built from the shipped models by CMake before this test
// compiles) reproduce the model files exactly.
#include <gtest/gtest.h>

#include "app/model/codegen.hpp"
#include "app/model/error.hpp"
#include "app/model/model_store.hpp"
#include "gen_hasel.hpp"
#include "gen_msd.hpp"
#include "gen_tendon.hpp"
#include "shared/forward.hpp"

using namespace nlsoft;
using namespace nlsoft::pipeline;

namespace {

template <class Cap, class Build>
void expect_same_outputs(const std::string& file, Build build) {
  const ModelFile f = load_model_file(std::string(NLSOFT_SOURCE_DIR) + "/app/models/" + file);
  const Model<HostCapacity> from_file = f.view();
  Model<Cap> generated;
  ASSERT_EQ(build(generated), Status::Ok);
  EXPECT_EQ(generated.hash, from_file.hash);
  ASSERT_EQ(generated.param_count, from_file.param_count);
  for (uint32_t i = 0; i < generated.param_count; ++i) ASSERT_EQ(generated.params[i], from_file.params[i]) << i;
  ForwardScratch<HostCapacity, float> s1;
  ForwardScratch<Cap, float> s2;
  float x[Dims<HostCapacity>::p], y1[HostCapacity::n], y2[HostCapacity::n];
  for (int row = 0; row < 20; ++row) {
    for (int i = 0; i < from_file.p(); ++i)
      x[i] = from_file.in_offset()[i] + (0.9f * std::sin(float(row * 7 + i))) / from_file.in_scale()[i];
    forward(from_file, x, y1, s1);
    forward(generated, x, y2, s2);
    for (int j = 0; j < from_file.n; ++j) EXPECT_EQ(y1[j], y2[j]);
  }
}

struct Tiny {
  static constexpr int m = 6, n = 3, w = 18, nd = 2, N = 1, Nc = 1, width = 4, layers = 4, weights = 64;
};

}  // namespace

TEST(Codegen, GeneratedHeadersReproduceTheShippedModels) {
  expect_same_outputs<HaselCapacity>("hasel.nlsm", [](Model<HaselCapacity>& m) { return gen_hasel::build(m); });
  expect_same_outputs<TendonCapacity>("tendon.nlsm", [](Model<TendonCapacity>& m) { return gen_tendon::build(m); });
  expect_same_outputs<MsdCapacity>("msd.nlsm", [](Model<MsdCapacity>& m) { return gen_msd::build(m); });
}

TEST(Codegen, TooSmallACapacityIsReported) {
  Model<Tiny> m;
  EXPECT_EQ(gen_hasel::build(m), Status::TooLarge);
  EXPECT_EQ(m.layer_count, 0);  // untouched
}

TEST(Codegen, RejectsABadNamespace) {
  const ModelFile f = load_model_file(std::string(NLSOFT_SOURCE_DIR) + "/app/models/msd.nlsm");
  EXPECT_THROW(generate_header(f, "2bad", "x"), PipelineError);
  EXPECT_THROW(generate_header(f, "a-b", "x"), PipelineError);
  EXPECT_NE(generate_header(f, "ok_name", "x").find("namespace ok_name"), std::string::npos);
}
