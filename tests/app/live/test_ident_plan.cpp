// What `ident` asks of the firmware before a run starts: identification runs
// at all (IDENT), and MIXED only where it is honoured (IDENT_MIXED), since a
// firmware without that capability ignores the option bit instead of
// refusing it.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "host/files/cli_error.hpp"
#include "app/live/ident_plan.hpp"

namespace nlsoft::console {
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
  EXPECT_NE(refusal(s, p::capability::kIdentMixed).find("no identification runs"), std::string::npos);
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
  const IdentPlan plan = plan_ident(w, 130.0, 6, 3, 18, IdentLine{115200, true});
  EXPECT_EQ(plan.start.signal, uint8_t(p::IdentSignal::Aprbs));
  EXPECT_EQ(plan.start.options, p::ident_options::kMixed);
  w.joint = true;
  EXPECT_THROW(check_ident_words(w), CliError);
  w.joint = false;
  w.signal = "prbs";
  EXPECT_THROW(check_ident_words(w), CliError);
}

}  // namespace
}  // namespace nlsoft::console
