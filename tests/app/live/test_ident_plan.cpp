// What `ident` asks of the firmware before a run starts: identification runs
// at all (IDENT), and MIXED only where it is honoured (IDENT_MIXED), since a
// firmware without that capability ignores the option bit instead of
// refusing it.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "host/files/cli_error.hpp"
#include "app/live/ident_plan.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::RigIdentChoice;

namespace {

namespace p = protocol;

std::string refusal(const p::IdentStart& s, uint32_t capabilities) {
  p::Info info;
  std::snprintf(info.firmware, sizeof info.firmware, "%s", "nlsoft-fw old");
  info.capabilities = capabilities;
  try {
    check_firmware_offers(s, info, 3);
  } catch (const CliError& e) {
    return e.what();
  }
  return "";
}

TEST(IdentPlan, MixedGoesOnlyToAFirmwareThatHonoursIt) {
  p::IdentStart s;
  s.signal = uint8_t(p::IdentSignal::Aprbs);
  EXPECT_EQ(refusal(s, p::capability::kIdent), "");
  s.options = p::ident_options::kMixed;
  const std::string old = refusal(s, p::capability::kIdent);
  EXPECT_NE(old.find("nlsoft-fw old"), std::string::npos) << old;
  EXPECT_NE(old.find("IDENT_MIXED"), std::string::npos) << old;
  EXPECT_NE(old.find("leave out --mixed"), std::string::npos) << old;
  EXPECT_EQ(refusal(s, p::capability::kIdent | p::capability::kIdentMixed), "");
  // A 1.3 firmware without IDENT was built without it (PROTOCOL.md 9.12), or predates it.
  const std::string none = refusal(s, p::capability::kIdentMixed);
  EXPECT_NE(none.find("was built without identification runs (IDENT_START)"), std::string::npos) << none;
  EXPECT_NE(none.find("leave out \"ident\""), std::string::npos) << none;
  EXPECT_NE(none.find("or it predates the service: update it"), std::string::npos) << none;
}

// The words: an unknown signal is answered with the list, and --mixed is
// refused with --joint and with prbs.
TEST(IdentPlan, WordsNameTheSignalsAndRefuseMixedWhereItCannotBe) {
  IdentWords w;
  w.duration = "10s";
  w.signal = "sine";
  try {
    check_ident_words(w);
    ADD_FAILURE() << "sine accepted";
  } catch (const CliError& e) {
    EXPECT_NE(std::string(e.what()).find("use steps, prbs, walk, chirp or aprbs"), std::string::npos) << e.what();
  }
  w.signal = "aprbs";
  w.mixed = true;
  EXPECT_NO_THROW(check_ident_words(w));
  const IdentPlan plan = plan_ident(w, 130.0, 6, 3, 18, IdentLine{115200, true}, nullptr);
  EXPECT_EQ(plan.start.signal, uint8_t(p::IdentSignal::Aprbs));
  EXPECT_EQ(plan.start.options, p::ident_options::kMixed);
  w.joint = true;
  EXPECT_THROW(check_ident_words(w), CliError);
  w.joint = false;
  w.signal = "prbs";
  EXPECT_THROW(check_ident_words(w), CliError);
}

// The band and amplitude the words leave out come from the rig file's
// [ident] (a signal's own table first), else ident's own; the plan says
// which, and the run's excitation records what was sent.
TEST(IdentPlan, WhatTheWordsLeaveOutComesFromTheRigFileAndTheWordsSayWhere) {
  Rig rig;
  rig.file = "bench.toml";
  rig.ident.all.amplitude = 0.6, rig.ident.all.amplitude_from = "[ident]";
  RigIdentChoice& steps = rig.ident.signal[size_t(ExcitationSignal::Steps)];
  steps.band_lo = 0.5, steps.band_hi = 5.0, steps.band_from = "[ident.steps]";
  const IdentLine sim{115200, true};
  IdentWords w;
  w.duration = "10s";
  w.signal = "steps";
  IdentPlan plan = plan_ident(w, 130.0, 6, 3, 18, sim, &rig);
  EXPECT_FLOAT_EQ(plan.start.amplitude, 0.6f);
  EXPECT_FLOAT_EQ(plan.start.band_lo, 0.5f);
  EXPECT_FLOAT_EQ(plan.start.band_hi, 5.0f);
  EXPECT_EQ(plan.excitation_words,
            "excitation: steps, band 0.5:5 Hz ([ident.steps] of bench.toml), amplitude 0.6 ([ident] of bench.toml), "
            "seed 1");
  EXPECT_EQ(nlohmann::json::parse(plan.excitation_json)["amplitude"], 0.6);

  // The words win over the file.
  w.amplitude = 1.0;
  w.band = "0.1:2";
  plan = plan_ident(w, 130.0, 6, 3, 18, sim, &rig);
  EXPECT_FLOAT_EQ(plan.start.amplitude, 1.0f);
  EXPECT_FLOAT_EQ(plan.start.band_lo, 0.1f);
  EXPECT_EQ(plan.excitation_words, "excitation: steps, band 0.1:2 Hz (--band), amplitude 1 (--amplitude), seed 1");

  // A signal without a table of its own: [ident]'s amplitude, ident's band.
  IdentWords prbs;
  prbs.duration = "10s";
  prbs.signal = "prbs";
  plan = plan_ident(prbs, 130.0, 6, 3, 18, sim, &rig);
  EXPECT_FLOAT_EQ(plan.start.amplitude, 0.6f);
  EXPECT_FLOAT_EQ(plan.start.band_lo, 0.05f);
  EXPECT_FLOAT_EQ(plan.start.band_hi, 2.0f);
  EXPECT_NE(plan.excitation_words.find("band 0.05:2 Hz (ident's default)"), std::string::npos) << plan.excitation_words;

  // No rig file known (a firmware of its own rig, no --rig): ident's own.
  IdentWords plain;
  plain.duration = "10s";
  plan = plan_ident(plain, 130.0, 6, 3, 18, sim, nullptr);
  EXPECT_FLOAT_EQ(plan.start.amplitude, 0.8f);
  EXPECT_EQ(plan.excitation_words,
            "excitation: aprbs, band 0.05:2 Hz (ident's default), amplitude 0.8 (ident's default), seed 1");

  // A file's band the firmware's rate cannot sample (an image of another
  // rate): refused naming where the band came from.
  IdentWords from_file;
  from_file.duration = "10s";
  from_file.signal = "steps";
  try {
    plan_ident(from_file, 8.0, 6, 3, 18, sim, &rig);
    ADD_FAILURE() << "a 5 Hz band accepted at 8 Hz";
  } catch (const CliError& e) {
    EXPECT_NE(std::string(e.what()).find("the band 0.5:5 ([ident.steps] of bench.toml) reaches past half the loop "
                                         "rate (4 Hz at 8 Hz)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
// hasel's board image (6 inputs, 3 outputs, 18 sensors at 130 Hz) follows
// each IDENT_SAMPLE with a SENSOR_HEALTH: 130 + 19 = 149 bytes a sample,
// which 115200 baud carries at decimation 3 (PROTOCOL.md's table), not the
// 2 that IDENT_SAMPLE alone would need.
TEST(IdentPlan, TheDecimationCountsTheSensorHealthThatFollowsEachSample) {
  EXPECT_EQ(ident_sample_wire_bytes(6, 3, 18), 130u);
  EXPECT_EQ(ident_sample_wire_bytes(6, 3, 18, true), 149u);
  EXPECT_EQ(ident_decimation_for(130.0, 6, 3, 18, 115200), 2);
  EXPECT_EQ(ident_decimation_for(130.0, 6, 3, 18, 115200, true), 3);
  IdentWords w;
  w.signal = "prbs";
  w.duration = "10s";
  IdentLine board{115200, false, true};
  const IdentPlan plan = plan_ident(w, 130.0, 6, 3, 18, board, nullptr);
  EXPECT_EQ(plan.start.decimation, 3);
  EXPECT_NE(plan.line_words.find("IDENT_SAMPLE and its SENSOR_HEALTH are 149 bytes"), std::string::npos)
      << plan.line_words;
}

}  // namespace nlsoft::console
