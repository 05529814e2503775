// The rig loader: one test per class of bad file, each asserting the exact
// file:line and key of the message, and good files up to the largest rig.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig.hpp"
#include "host/rig/rig_plant.hpp"
#include "rig_text.hpp"

namespace nlsoft::host {
namespace {

const char* kBase = R"(name = "probe"
rate_hz = 100.0
nd = 2
dd = 2

[[input]]
name = "u1"
unit = "V"
min = 0.0
max = 1.0
neutral = 0.5
pwm = "PC6"

[[input]]
name = "u2"
min = -1.0
max = 1.0
neutral = 0.0
pwm = "PC7"

[[output]]
name = "x"
unit = "mm"
min = -10.0
max = 10.0

[[sensor]]
name = "l1"
source = "adc"
adc = 0
gain = 2.0
offset = 0.1

[controller]
Q = [1.0]
Lambda = [1.0, 1.0]
s = 1e-20
b = 1e-5
r = 400.0
N = 3
Nc = 1
eps = 0.01
)";

using rig_text::error_of;
using rig_text::expect_error;
using rig_text::line_of;

// kBase with the nth occurrence of `from` replaced by `to`.
std::string edit(const std::string& from, const std::string& to, int nth = 1, std::string text = kBase) {
  return rig_text::replaced(std::move(text), from, to, nth);
}

TEST(RigLoader, BaseFileLoadsWithEveryValue) {
  const Rig r = parse_rig(kBase, "my.toml");
  EXPECT_EQ(r.name, "probe");
  EXPECT_EQ(r.rate_hz, 100.0);
  EXPECT_EQ(r.m(), 2);
  EXPECT_EQ(r.n(), 1);
  EXPECT_EQ(r.w(), 1);
  EXPECT_EQ(r.inputs[0].pwm, "PC6");
  EXPECT_EQ(r.inputs[1].min, -1.0);
  EXPECT_EQ(r.outputs[0].span, 20.0);  // max - min when not given
  EXPECT_EQ(r.outputs[0].source, OutputSource::None);
  EXPECT_EQ(r.sensors[0].source, SensorSource::Adc);
  EXPECT_EQ(r.sensors[0].gain, 2.0);
  EXPECT_EQ(r.controller.N, 3);
  EXPECT_EQ(r.controller.N1, 1);  // default
  EXPECT_EQ(r.controller.mode, DerivMode::Exact);
  EXPECT_EQ(r.board, "stm32f4");
  EXPECT_EQ(r.plant.kind, nullptr);
}

// The rate is a period the loop takes: 1 mHz (a slow process) to 100 kHz,
// and at least 1 Hz where a simulated plant steps at it (at most 1 s a step).
TEST(RigLoader, ARateNoLoopRunsAtIsRefusedAtItsLine) {
  expect_error(edit("rate_hz = 100.0", "rate_hz = 1e308"), 2, "rate_hz", "must be in [0.001, 100000] Hz, not 1e+308");
  expect_error(edit("rate_hz = 100.0", "rate_hz = 1e-4"), 2, "rate_hz", "must be in [0.001, 100000] Hz, not 0.0001");
  EXPECT_EQ(parse_rig(edit("rate_hz = 100.0", "rate_hz = 0.25"), "my.toml").rate_hz, 0.25);
}

// Text lands in recorded columns, plots and generated C++: names keep a
// grammar, units and descriptions one line, a model file its folder.
TEST(RigLoader, TextThatWouldLeaveItsPlaceIsRefusedAtItsLine) {
  const int name_line = line_of(kBase, "name = \"u1\"");
  for (const char* bad : {"a\\n#include \\\"/etc/hostname\\\"", "1st", "", "a b", "x\\\"", "a*/b", "$(x)",
                          "abcdefghijklmnopqrstuvwxyz0123456"})
    expect_error(edit("name = \"u1\"", std::string("name = \"") + bad + "\""), name_line, "[[input]] #1 name",
                 "is not a name: a letter or '_', then letters, digits, '_', '.' or '-', at most 32 characters");
  for (const char* good : {"_a", "tip.x", "left-1", "abcdefghijklmnopqrstuvwxyz012345"})
    EXPECT_EQ(parse_rig(edit("name = \"u1\"", std::string("name = \"") + good + "\""), "my.toml").inputs[0].name,
              good);
  expect_error(edit("unit = \"V\"", "unit = \"V\\n#error x\""), line_of(kBase, "unit = \"V\""), "[[input]] #1 unit",
               "holds the control character 0x0a: one line of text");
  EXPECT_EQ(parse_rig(edit("unit = \"V\"", "unit = \"\u00b5m \\\"*/ $(x)\""), "my.toml").inputs[0].unit,
            "\u00b5m \"*/ $(x)");
  const std::string model = std::string(kBase) + "\n[model]\nfile = \"../../../../../../etc/passwd\"\n";
  expect_error(model, line_of(model, "file = "), "[model] file",
               "'../../../../../../etc/passwd' is not a file name among the models (no '/')");
  EXPECT_EQ(parse_rig(std::string(kBase) + "\n[model]\nfile = \"my.nlsm\"\n", "my.toml").model.file, "my.nlsm");
}

TEST(RigLoader, MissingKeyNamesTheTableLine) {
  expect_error(edit("max = 1.0\n", "", 1), line_of(kBase, "[[input]]", 1), "[[input]] #1 max", "missing key");
  expect_error(edit("rate_hz = 100.0\n", ""), 1, "rate_hz", "missing key");
  expect_error(edit("eps = 0.01\n", ""), line_of(kBase, "[controller]"), "[controller] eps", "missing key");
}

TEST(RigLoader, NanIsRefusedWhereverItIs) {
  expect_error(edit("min = 0.0", "min = nan"), line_of(kBase, "min = 0.0"), "[[input]] #1 min", "must be finite, not nan");
  expect_error(edit("rate_hz = 100.0", "rate_hz = inf"), 2, "rate_hz", "must be finite, not inf");
  // The controller's defaults take PARAM_SET's own finiteness check.
  expect_error(edit("s = 1e-20", "s = nan"), line_of(kBase, "s = 1e-20"), "[controller] s", "must be finite");
  expect_error(edit("Q = [1.0]", "Q = [-nan]"), line_of(kBase, "Q = [1.0]"), "[controller] Q[0]", "must be finite");
}

TEST(RigLoader, MinNotBelowMaxNamesBothLines) {
  const std::string t = edit("max = 1.0", "max = -1.0", 2);
  expect_error(t, line_of(t, "max = -1.0"), "[[input]] #2 max",
               "must be > min (-1 at line " + std::to_string(line_of(t, "min = -1.0")) + ")");
  const std::string o = edit("max = 10.0", "max = -10.0");
  expect_error(o, line_of(o, "max = -10.0"), "[[output]] #1 max",
               "must be > min (-10 at line " + std::to_string(line_of(o, "min = -10.0")) + ")");
  const std::string nz = edit("neutral = 0.5", "neutral = 1.5");
  expect_error(nz, line_of(nz, "neutral = 1.5"), "[[input]] #1 neutral", "must lie in [min, max] = [0, 1]");
}

TEST(RigLoader, NoOutputsIsNEqualsZero) {
  const std::string t = edit("[[output]]\nname = \"x\"\nunit = \"mm\"\nmin = -10.0\nmax = 10.0\n", "");
  expect_error(t, 1, "[[output]]", "none given: a rig controls 1 to 6 outputs (n = 0)");
  // Q has no element to weigh then, but the count of outputs is what is wrong.
}

TEST(RigLoader, NoInputsIsMEqualsZero) {
  std::string t = kBase;
  t = edit("[[input]]\nname = \"u1\"\nunit = \"V\"\nmin = 0.0\nmax = 1.0\nneutral = 0.5\npwm = \"PC6\"\n", "", 1, t);
  t = edit("[[input]]\nname = \"u2\"\nmin = -1.0\nmax = 1.0\nneutral = 0.0\npwm = \"PC7\"\n", "", 1, t);
  expect_error(t, 1, "[[input]]", "(m = 0)");
}

std::string input_table(int i, const std::string& pin) {
  std::string s = "[[input]]\nname = \"u" + std::to_string(i) + "\"\nmin = 0.0\nmax = 1.0\nneutral = 0.0\n";
  if (!pin.empty()) s += "pwm = \"" + pin + "\"\n";
  return s + "\n";
}
std::string output_table(int i) {
  return "[[output]]\nname = \"y" + std::to_string(i) + "\"\nunit = \"mm\"\nmin = -1.0\nmax = 1.0\n\n";
}
std::string sensor_table(int i, int adc) {
  std::string s = "[[sensor]]\nname = \"l" + std::to_string(i) + "\"\n";
  return s + (adc >= 0 ? "source = \"adc\"\nadc = " + std::to_string(adc) + "\n\n" : "source = \"none\"\n\n");
}

// A rig of m inputs, n outputs, w sensors: PWM and ADC pins while the board
// has them, then none.
std::string rig_of(int m, int n, int w, int N = 128, int Nc = 4) {
  const char* pwm[] = {"PC6", "PC7", "PC8", "PC9", "PB6", "PB7"};
  const int adc[] = {0, 1, 4, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  std::string s = "name = \"big\"\nrate_hz = 50\nnd = 4\ndd = 4\n\n";
  for (int i = 0; i < m; ++i) s += input_table(i, i < 6 ? pwm[i] : "");
  for (int i = 0; i < n; ++i) s += output_table(i);
  for (int i = 0; i < w; ++i) s += sensor_table(i, i < 13 ? adc[i] : -1);
  s += "[controller]\nQ = [";
  for (int i = 0; i < n; ++i) s += std::string(i ? ", " : "") + "1.0";
  s += "]\nLambda = [";
  for (int i = 0; i < m; ++i) s += std::string(i ? ", " : "") + "1.0";
  s += "]\ns = 1e-20\nb = 0.5\nr = 1.0\nN = " + std::to_string(N) + "\nNc = " + std::to_string(Nc) + "\neps = 1e-3\n";
  return s;
}

TEST(RigLoader, LargestRigLoads) {
  const Rig r = parse_rig(rig_of(8, 6, 32), "big.toml");
  EXPECT_EQ(r.m(), 8);
  EXPECT_EQ(r.n(), 6);
  EXPECT_EQ(r.w(), 32);
  EXPECT_EQ(r.nd, 4);
  EXPECT_EQ(r.controller.N, 128);
  EXPECT_EQ(r.controller.Nc, 4);
  EXPECT_EQ(r.controller.Q.size(), 6u);
  EXPECT_EQ(r.sensors[12].adc, 15);
  EXPECT_EQ(r.sensors[13].source, SensorSource::None);
  EXPECT_EQ(r.inputs[7].pwm, "");
}

TEST(RigLoader, OverCapacityNamesTheFirstTableTooMany) {
  const std::string m9 = rig_of(9, 1, 0);
  expect_error(m9, line_of(m9, "[[input]]", 9), "[[input]] #9", "over capacity: at most m = 8 inputs");
  const std::string n7 = rig_of(1, 7, 0);
  expect_error(n7, line_of(n7, "[[output]]", 7), "[[output]] #7", "over capacity: at most n = 6 outputs");
  const std::string w33 = rig_of(1, 1, 33);
  expect_error(w33, line_of(w33, "[[sensor]]", 33), "[[sensor]] #33", "over capacity: at most w = 32 sensors");
  const std::string nc5 = rig_of(1, 1, 0, 128, 5);
  expect_error(nc5, line_of(nc5, "Nc = 5"), "[controller] Nc", "over capacity: 5 exceeds the controller's Nc <= 4");
  const std::string nd33 = edit("nd = 2", "nd = 33");
  expect_error(nd33, 3, "nd", "must be in [1, 32]");
}

// nd and dd left out, or "auto": train searches the history length; the rig
// holds the longest its inputs leave room for until a model gives its own.
// Anything else that is not a length is refused at its line.
TEST(RigLoader, HistoriesLeftOutOrAutoAreLeftToTrain) {
  const Rig r = parse_rig(edit("dd = 2", "dd = \"auto\"", 1, edit("nd = 2", "nd = \"auto\"")), "my.toml");
  EXPECT_TRUE(r.lags_auto);
  EXPECT_EQ(r.nd, std::min(32, (88 - r.w()) / (r.m() + r.n())));
  EXPECT_EQ(r.dd, r.nd);
  const Rig left_out = parse_rig(edit("dd = 2\n", "", 1, edit("nd = 2\n", "")), "my.toml");
  EXPECT_TRUE(left_out.lags_auto);
  EXPECT_EQ(left_out.nd, r.nd);
  EXPECT_FALSE(parse_rig(kBase, "my.toml").lags_auto);
  expect_error(edit("nd = 2", "nd = \"atuo\""), 3, "nd", "'atuo' is not a history length: an integer, or \"auto\"");
  expect_error(edit("nd = 2", "nd = \"auto\""), 4, "dd",
               "is set while nd is left to train's search: give both (equal) or neither");
  expect_error(edit("nd = 2", "nd = 0"), 3, "nd", "must be in [1, 32], not 0");
}

// Long histories for a narrow rig, short ones for a wide rig: the limit is the
// network's input length p = nd m + dd n + w, not nd alone.
// INFO's platform number is the file's to give: a rig named like a shipped
// one does not get that rig's number by its name, and a number the
// protocol has not assigned is refused at its line.
TEST(RigLoader, ThePlatformNumberIsTheFilesNotTheNames) {
  const std::string named = edit("name = \"probe\"", "name = \"hasel\"");
  const Rig rig = parse_rig(named, "my.toml");
  EXPECT_EQ(rig.info_platform, 255);
  EXPECT_EQ(firmware_rig(rig).platform, PlatformId::Custom);
  const Rig given = parse_rig(edit("rate_hz = 100.0", "info_platform = 2\nrate_hz = 100.0"), "my.toml");
  EXPECT_EQ(firmware_rig(given).platform, PlatformId::Tendon);
  const std::string bad = edit("rate_hz = 100.0", "info_platform = 3\nrate_hz = 100.0");
  expect_error(bad, line_of(bad, "info_platform"), "info_platform", "must be in [0, 2]");
}

TEST(RigLoader, HistoriesAreBoundByTheInputLength) {
  auto with_nd = [](std::string t, int nd) {
    for (const char* k : {"nd = 4", "dd = 4"}) {
      const size_t at = t.find(k);
      t.replace(at, std::string(k).size(), std::string(k).substr(0, 5) + std::to_string(nd));
    }
    return t;
  };
  EXPECT_EQ(parse_rig(with_nd(rig_of(1, 1, 0), 32), "siso.toml").nd, 32);
  EXPECT_EQ(parse_rig(with_nd(rig_of(1, 1, 24), 32), "siso.toml").nd, 32);  // 32 + 32 + 24 = 88
  const std::string wide = with_nd(rig_of(8, 6, 32), 5);
  expect_error(wide, 3, "nd",
               "the network's input p = nd m + dd n + w = 5*8 + 5*6 + 32 = 102 exceeds 88: shorten the histories to "
               "nd = dd <= 4");
  const std::string siso = with_nd(rig_of(1, 1, 25), 32);
  expect_error(siso, 3, "nd",
               "the network's input p = nd m + dd n + w = 32*1 + 32*1 + 25 = 89 exceeds 88: shorten the histories to "
               "nd = dd <= 31");
}

TEST(RigLoader, UnknownPinListsTheBoardsPins) {
  const std::string t = edit("pwm = \"PC7\"", "pwm = \"PA9\"");
  expect_error(t, line_of(t, "pwm = \"PA9\""), "[[input]] #2 pwm",
               "unknown pin 'PA9' on board stm32f4 (PWM pins: PC6, PC7, PC8, PC9, PB6, PB7)");
  // ADC1 channel 2 carries USART2 on a Nucleo-64: not in the table.
  const std::string a = edit("adc = 0", "adc = 2");
  expect_error(a, line_of(a, "adc = 2"), "[[sensor]] #1 adc",
               "unknown pin: ADC1 channel 2 is not wired on board stm32f4 (channels: 0, 1, 4, 6, 7, 8, 9, 10, 11, 12, 13, "
               "14, 15)");
  // More analogue sensors than the board has channels: the 14th must say
  // where it is read, and any channel it names is taken or absent.
  const std::string w14 = rig_of(1, 1, 14) + "";
  std::string over = w14;
  over = edit("name = \"l13\"\nsource = \"none\"", "name = \"l13\"\nsource = \"adc\"\nadc = 0", 1, over);
  expect_error(over, line_of(over, "adc = 0", 2), "[[sensor]] #14 adc",
               "ADC1 channel 0 is already used by [[sensor]] #1 (line " + std::to_string(line_of(over, "adc = 0")) + ")");
}

TEST(RigLoader, UnknownKeyListsTheKnownOnes) {
  const std::string t = edit("pwm = \"PC6\"", "pmw = \"PC6\"");
  expect_error(t, line_of(t, "pmw"), "[[input]] #1 pmw",
               "unknown key (known: name, unit, min, max, neutral, pwm, servo, goal_per_unit, goal_at_neutral)");
  const std::string tab = std::string(kBase) + "\n[plnt]\nkind = \"hasel\"\n";
  expect_error(tab, line_of(tab, "[plnt]"), "plnt",
               "unknown table (known: name, description, info_platform, rate_hz, nd, dd, board, input, output, sensor, device, controller, "
               "model, plant, reference, ident, pid, firmware)");
  const std::string c = edit("eps = 0.01", "eps = 0.01\nlambda = [1.0, 1.0]");
  expect_error(c, line_of(c, "lambda ="), "[controller] lambda", "unknown key (known: Q, Lambda, s, b, r, N, N1, Nc, eps,");
}

TEST(RigLoader, WrongTypeSaysWhatWasExpected) {
  expect_error(edit("rate_hz = 100.0", "rate_hz = \"fast\""), 2, "rate_hz", "expected a number, got a string");
  const std::string n = edit("N = 3", "N = 3.5");
  expect_error(n, line_of(n, "N = 3.5"), "[controller] N", "expected an integer, got a number");
  const std::string q = edit("Q = [1.0]", "Q = 1.0");
  expect_error(q, line_of(q, "Q = 1.0"), "[controller] Q", "expected an array, got a number");
  const std::string nm = edit("name = \"u1\"", "name = 1");
  expect_error(nm, line_of(nm, "name = 1"), "[[input]] #1 name", "expected a string, got an integer");
  const std::string tbl = edit("nd = 2", "plant = \"hasel\"\nnd = 2");
  expect_error(tbl, 3, "plant", "expected a table [plant], got a string");
}

TEST(RigLoader, DuplicateNamesAndPinsNameTheFirstUse) {
  const std::string t = edit("name = \"l1\"", "name = \"x\"");
  expect_error(t, line_of(t, "name = \"x\"", 2), "[[sensor]] #1 name",
               "'x' is already the name of [[output]] #1 (line " + std::to_string(line_of(t, "name = \"x\"")) + ")");
  const std::string p = edit("pwm = \"PC7\"", "pwm = \"PC6\"");
  expect_error(p, line_of(p, "pwm = \"PC6\"", 2), "[[input]] #2 pwm",
               "PC6 is already used by [[input]] #1 (line " + std::to_string(line_of(p, "pwm = \"PC6\"")) + ")");
}

// A signal's amplitude and band, and the tables that set them.
void expect_choice(const RigIdentChoice& c, double amplitude, const std::string& amplitude_from, double lo, double hi,
                   const std::string& band_from) {
  EXPECT_EQ(c.amplitude, amplitude);
  EXPECT_EQ(c.amplitude_from, amplitude_from);
  EXPECT_EQ(c.band_lo, lo);
  EXPECT_EQ(c.band_hi, hi);
  EXPECT_EQ(c.band_from, band_from);
}

// ident's defaults: [ident] for every signal, [ident.SIGNAL] over it, field
// by field; each remembers its table, which ident names when it uses it.
TEST(RigLoader, IdentDefaultsAreASignalsOwnTableOverTheWholeSection) {
  const std::string t = std::string(kBase) +
                        "\n[ident]\namplitude = 0.6\nband = [0.1, 4.0]\n\n[ident.steps]\nband = [0.5, 5.0]\n\n"
                        "[ident.prbs]\namplitude = 1.0\n";
  const Rig r = parse_rig(t, "my.toml");
  expect_choice(r.ident.for_signal(ExcitationSignal::Steps), 0.6, "[ident]", 0.5, 5.0, "[ident.steps]");
  expect_choice(r.ident.for_signal(ExcitationSignal::Prbs), 1.0, "[ident.prbs]", 0.1, 4.0, "[ident]");
  expect_choice(r.ident.for_signal(ExcitationSignal::Walk), 0.6, "[ident]", 0.1, 4.0, "[ident]");
  // Without [ident] the file sets nothing: ident's own defaults stand.
  expect_choice(parse_rig(kBase, "my.toml").ident.for_signal(ExcitationSignal::Aprbs), 0.0, "", 0.0, 0.0, "");
}

// IDENT_START's rules (shared/excitation.hpp), refused in the file at their
// line rather than by the firmware at the run's start.
TEST(RigLoader, IdentDefaultsTakeIdentStartsChecksAtTheirLine) {
  auto with = [](const std::string& tail) { return std::string(kBase) + "\n" + tail; };
  std::string t = with("[ident.steps]\namplitude = 1.5\n");
  expect_error(t, line_of(t, "amplitude = 1.5"), "[ident.steps] amplitude", "must be in (0, 1], the fraction");
  t = with("[ident]\nband = [2.0, 1.0]\n");
  expect_error(t, line_of(t, "band ="), "[ident] band", "its lower edge 2 Hz is above its upper 1");
  t = with("[ident]\nband = [0.0, 1.0]\n");
  expect_error(t, line_of(t, "band ="), "[ident] band", "its lower edge must be > 0 Hz, not 0");
  t = with("[ident.walk]\nband = [1.0, 60.0]\n");
  expect_error(t, line_of(t, "band ="), "[ident.walk] band", "reaches past half the loop rate (50 Hz at rate_hz = 100)");
  t = with("[ident]\nband = [1.0]\n");
  expect_error(t, line_of(t, "band ="), "[ident] band", "expected [LO, HI] in Hz, 2 numbers, got 1");
  t = with("[ident.sine]\nband = [1.0, 2.0]\n");
  expect_error(t, line_of(t, "[ident.sine]"), "[ident] sine",
               "unknown table (known: amplitude, band, steps, prbs, walk, chirp, aprbs)");
  t = with("[ident.steps]\nseed = 3\n");
  expect_error(t, line_of(t, "seed = 3"), "[ident.steps] seed", "unknown key (known: amplitude, band)");
  // A table that sets no band holds none to the rate: ident's own band is fitted to it when it runs.
  EXPECT_NO_THROW(parse_rig(edit("rate_hz = 100.0", "rate_hz = 2.0", 1, with("[ident]\namplitude = 0.5\n")), "my.toml"));
  t = with("[ident]\nsteps = 1.0\n");
  expect_error(t, line_of(t, "steps = 1.0"), "[ident] steps", "expected a table [ident.steps], got a number");
}

// The controller's defaults meet PARAM_SET's checks (shared/params.hpp).
TEST(RigLoader, ControllerDefaultsTakeTheParameterChecks) {
  const std::string q = edit("Q = [1.0]", "Q = [-1.0]");
  expect_error(q, line_of(q, "Q = [-1.0]"), "[controller] Q[0]", "out of range: -1 is not in [0, 1e+12] (the range PARAM_SET accepts)");
  const std::string qn = edit("Q = [1.0]", "Q = [1.0, 2.0]");
  expect_error(qn, line_of(qn, "Q = [1.0, 2.0]"), "[controller] Q", "expects 1 values (one per [[output]]), got 2");
  const std::string nc = edit("Nc = 1", "Nc = 4");
  expect_error(nc, line_of(nc, "Nc = 4"), "[controller] Nc",
               "must be <= N (3 at line " + std::to_string(line_of(nc, "N = 3")) + ")");
  const std::string r = edit("r = 400.0", "r = 0.0");
  expect_error(r, line_of(r, "r = 0.0"), "[controller] r", "out of range: 0 is not in [1e-06, 1e+07]");
  const std::string it = edit("eps = 0.01", "eps = 0.01\nnr_max_iter = 21");
  expect_error(it, line_of(it, "nr_max_iter"), "[controller] nr_max_iter",
               "out of range: 21 is not in [1, 20], a whole number");
  const std::string mode = edit("eps = 0.01", "eps = 0.01\nmode = \"newton\"");
  expect_error(mode, line_of(mode, "mode ="), "[controller] mode", "'newton' is not one of: exact, fd");
  const std::string u = edit("max = 1.0", "max = 2e6");
  expect_error(u, line_of(u, "max = 2e6"), "[[input]] #1 max", "out of range: 2000000 is not in [-1000000, 1000000]");
}

// A simulated plant steps at most 1 s: a slower rig has no stand-in.
TEST(RigLoader, ARigWithAPlantRunsAtLeastOnceASecond) {
  const std::string slow_plant = edit("rate_hz = 50", "rate_hz = 0.5", 1, rig_of(1, 1, 0)) + "\n[plant]\nkind = \"msd\"\n";
  expect_error(slow_plant, 2, "rate_hz", "must be at least 1 Hz with a [plant] (line " +
                                             std::to_string(line_of(slow_plant, "kind = \"msd\"")) +
                                             "): a simulated plant steps at most 1 s, not 0.5");
}

TEST(RigLoader, PlantMustHaveTheFilesDimensions) {
  const std::string t = std::string(kBase) + "\n[plant]\nkind = \"tendon\"\n";
  expect_error(t, line_of(t, "kind = \"tendon\""), "[plant] kind",
               "plant 'tendon' has n = 3, but the file has 1 [[output]] tables");
  const std::string msd = rig_of(1, 1, 0) + "\n[plant]\nkind = \"msd\"\n";
  // Another rate is the rig's own: the plant steps at the rig's period.
  EXPECT_EQ(parse_rig(msd, "t.toml").rate_hz, 50.0);
  const std::string k = std::string(kBase) + "\n[plant]\nkind = \"robot\"\n";
  expect_error(k, line_of(k, "kind = \"robot\""), "[plant] kind", "'robot' is not one of: msd, hasel, tendon");
}

// Every kind a rig file names is read once, here, into the value it stands
// for: an unknown one is refused at its line with the known ones listed,
// never taken for a default.
TEST(RigLoader, EveryKindIsOneOfItsValuesOrRefusedAtItsLine) {
  struct Case {
    std::string text, needle, label, what;
  };
  const std::string base(kBase);
  const std::vector<Case> cases = {
      {base + "\n[plant]\nkind = \"Hasel\"\n", "kind = \"Hasel\"", "[plant] kind",
       "'Hasel' is not one of: msd, hasel, tendon, generic"},
      {base + "\n[reference]\nkind = \"circle\"\n", "kind = \"circle\"", "[reference] kind",
       "'circle' is not one of: infinity, pringle, diagonal, swirl, steps"},
      {base + "\n[model]\n[[model.layer]]\nkind = \"lstm\"\nunits = 1\n", "kind = \"lstm\"",
       "[[model.layer]] #1 kind", "'lstm' is not one of: dense, gru"},
      {base + "\n[model]\n[[model.layer]]\nkind = \"dense\"\nunits = 1\nactivation = \"softmax\"\n",
       "activation = \"softmax\"", "[[model.layer]] #1 activation", "'softmax' is not one of: "},
      {edit("eps = 0.01", "eps = 0.01\nfeedback = \"both\""), "feedback =", "[controller] feedback",
       "'both' is not one of: predicted, measured"},
      {edit("eps = 0.01", "eps = 0.01\nmode = \"newton\""), "mode =", "[controller] mode",
       "'newton' is not one of: exact, fd"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.label);
    expect_error(c.text, line_of(c.text, c.needle), c.label, c.what);
  }
}

TEST(RigLoader, ModelLayersEndInTheOutputs) {
  const std::string t = std::string(kBase) +
                        "\n[model]\n[[model.layer]]\nkind = \"gru\"\nunits = 5\n[[model.layer]]\nkind = \"dense\"\n"
                        "units = 3\nactivation = \"tanh\"\n";
  expect_error(t, line_of(t, "units = 3"), "[[model.layer]] #2 units",
               "the last layer predicts the outputs: must be n = 1");
  const std::string g = std::string(kBase) + "\n[model]\n[[model.layer]]\nkind = \"gru\"\nunits = 17\n";
  expect_error(g, line_of(g, "units = 17"), "[[model.layer]] #1 units", "must be in [1, 16] (a GRU is 3 x units wide");
  // A kind whose activations are its own (shared/layer_kind.hpp) takes none from the file.
  const std::string a = std::string(kBase) +
                        "\n[model]\n[[model.layer]]\nkind = \"gru\"\nunits = 5\nactivation = \"relu\"\n"
                        "[[model.layer]]\nkind = \"dense\"\nunits = 1\n";
  expect_error(a, line_of(a, "activation = \"relu\""), "[[model.layer]] #1 activation",
               "not for kind = \"gru\" (a GRU's activations are fixed)");
}

// [pid]: what Pid::configure takes, on a rig whose inputs and outputs pair up.
TEST(RigLoader, PidGainsAreReadAndCheckedWhereWritten) {
  // kBase with one input for its one output.
  const std::string one = edit("Lambda = [1.0, 1.0]", "Lambda = [1.0]", 1,
                               edit("[[input]]\nname = \"u2\"\nmin = -1.0\nmax = 1.0\nneutral = 0.0\npwm = \"PC7\"\n\n", ""));
  const Rig r = parse_rig(one + "\n[pid]\nkp = 2.0\nki = 0.5\nd_filter_tau = 0.01\n", "my.toml");
  ASSERT_TRUE(r.pid.given);
  EXPECT_EQ(r.pid.kp, 2.0);
  EXPECT_EQ(r.pid.ki, 0.5);
  EXPECT_EQ(r.pid.kd, 0.0);
  EXPECT_EQ(r.pid.output_scale, 1.0);
  EXPECT_EQ(r.pid.d_filter_tau, 0.01);
  EXPECT_FALSE(parse_rig(one, "my.toml").pid.given);
  struct Case {
    std::string text, needle, label, what;
  } cases[] = {
      {one + "\n[pid]\nkp = -1.0\n", "kp = -1.0", "[pid] kp", "must be >= 0, not -1"},
      {one + "\n[pid]\nkd = nan\n", "kd = nan", "[pid] kd", "must be finite"},
      {one + "\n[pid]\noutput_scale = 0.0\n", "output_scale", "[pid] output_scale", "must not be 0"},
      {one + "\n[pid]\nkp = 1.0\nkq = 2.0\n", "kq", "[pid] kq", "unknown key"},
      {one + "\n[pid]\noutput_scale = 2.0\n", "[pid]", "[pid]", "give kp, ki or kd > 0"},
      {std::string(kBase) + "\n[pid]\nkp = 1.0\n", "[pid]", "[pid]",
       "needs as many inputs as outputs, at most 8 (this rig: m = 2, n = 1)"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.label);
    expect_error(c.text, line_of(c.text, c.needle), c.label, c.what);
  }
}

TEST(RigLoader, HistoryLengthsMustAgree) {
  const std::string t = edit("dd = 2", "dd = 3");
  expect_error(t, 4, "dd", "must equal nd (2 at line 3)");
}

TEST(RigLoader, TomlSyntaxErrorNamesItsLine) {
  const std::string t = edit("unit = \"mm\"", "unit = \"mm");
  const RigError e = error_of(t);
  EXPECT_EQ(e.line, line_of(t, "unit = \"mm"));
  EXPECT_EQ(std::string(e.what()).rfind("my.toml:" + std::to_string(e.line) + ": ", 0), 0u) << e.what();
}

TEST(RigLoader, UnreadableFileIsNamed) {
  try {
    load_rig("/nonexistent/rig.toml");
    FAIL() << "loaded a missing file";
  } catch (const RigError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/rig.toml: cannot read rig file: No such file or directory");
  }
  // What is there but no rig file is said as what it is (and /dev/zero is not read until memory runs out).
  for (const auto& [path, what] : {std::pair<std::string, std::string>{"/dev/zero", "a character device"},
                                   {"/tmp", "a directory"}}) {
    try {
      load_rig(path);
      FAIL() << "loaded " << path;
    } catch (const RigError& e) {
      EXPECT_EQ(std::string(e.what()), "cannot read " + path + ": it is " + what + ", not a rig file");
    }
  }
}


// ---------------------------------------------------------------- [plant] kind = "generic"

const char* kGenericPlant = R"(
[plant]
kind = "generic"
coupling = [[2.0, -1.0]]
output_offset = [1.0]
output_tau = [0.02]
sensor_map = [[1.0, 0.0, 0.5]]
sensor_noise = [0.01]

[[plant.actuator]]
gain = 3.0
shape = "tanh"
knee = 0.2
play = 0.01
tau = 0.05

[[plant.actuator]]
shape = "power"
exponent = 2.0
)";

const std::string kGeneric = std::string(kBase) + kGenericPlant;

std::string generic_edit(const std::string& from, const std::string& to, int nth = 1) {
  return edit(from, to, nth, kGeneric);
}

TEST(RigLoader, GenericPlantLoadsEveryKeyIntoTheSpec) {
  const Rig r = parse_rig(kGeneric, "my.toml");
  ASSERT_TRUE(has_generic_plant(r));
  ASSERT_EQ(r.plant.actuators.size(), 2u);
  EXPECT_EQ(r.plant.actuators[0].shape, GenericShape::Tanh);
  EXPECT_EQ(r.plant.actuators[1].gain, 1.0);  // default
  const GenericPlantSpec s = generic_plant_spec(r);
  EXPECT_EQ(generic_spec_problem(s), nullptr);
  EXPECT_EQ(s.m, 2);
  EXPECT_EQ(s.n, 1);
  EXPECT_EQ(s.w, 1);
  EXPECT_FLOAT_EQ(s.dt, 0.01f);  // 1 / rate_hz
  EXPECT_EQ(s.input[0].min, 0.0f);
  EXPECT_EQ(s.input[0].neutral, 0.5f);
  EXPECT_EQ(s.input[0].gain, 3.0f);
  EXPECT_EQ(s.input[0].shape, GenericShape::Tanh);
  EXPECT_EQ(s.input[0].knee, 0.2f);
  EXPECT_EQ(s.input[0].play, 0.01f);
  EXPECT_EQ(s.input[0].tau, 0.05f);
  EXPECT_EQ(s.input[1].shape, GenericShape::Power);
  EXPECT_EQ(s.input[1].exponent, 2.0f);
  EXPECT_EQ(s.input[1].tau, 0.0f);
  EXPECT_EQ(s.output[0].lo, -10.0f);  // the [[output]]'s reach is the box
  EXPECT_EQ(s.output[0].hi, 10.0f);
  EXPECT_EQ(s.output[0].offset, 1.0f);
  EXPECT_EQ(s.output[0].tau, 0.02f);
  EXPECT_EQ(s.B[0][0], 2.0f);
  EXPECT_EQ(s.B[0][1], -1.0f);
  EXPECT_EQ(s.C[0][2], 0.5f);
  EXPECT_EQ(s.sensor[0].offset, 0.0f);  // default
  EXPECT_EQ(s.sensor[0].noise, 0.01f);
  // output_offset defaults to the middle of the output's range.
  const Rig mid = parse_rig(generic_edit("output_offset = [1.0]\n", ""), "my.toml");
  EXPECT_EQ(mid.plant.output_offset, std::vector<double>{0.0});
}

TEST(RigLoader, GenericPlantMatricesMustHaveTheFilesSizes) {
  std::string t = generic_edit("coupling = [[2.0, -1.0]]", "coupling = [[2.0, -1.0], [1.0, 1.0]]");
  expect_error(t, line_of(t, "coupling"), "[plant] coupling",
               "expected n = 1 rows (one per [[output]]), got 2");
  t = generic_edit("coupling = [[2.0, -1.0]]", "coupling = [[2.0, -1.0, 4.0]]");
  expect_error(t, line_of(t, "coupling"), "[plant] coupling[0]",
               "expected m = 2 numbers (one per [[input]]), got 3");
  t = generic_edit("sensor_map = [[1.0, 0.0, 0.5]]", "sensor_map = [\n  [1.0, 0.0],\n]");
  expect_error(t, line_of(t, "[1.0, 0.0]"), "[plant] sensor_map[0]",
               "expected m + n = 3 numbers (one per [[input]], then one per [[output]]), got 2");
  t = generic_edit("output_tau = [0.02]", "output_tau = [0.02, 0.0]");
  expect_error(t, line_of(t, "output_tau"), "[plant] output_tau", "expected n = 1 numbers (one per [[output]]), got 2");
  t = generic_edit("coupling = [[2.0, -1.0]]", "coupling = [2.0]");
  expect_error(t, line_of(t, "coupling"), "[plant] coupling[0]", "expected an array (a row), got a number");
  t = generic_edit("sensor_map = [[1.0, 0.0, 0.5]]\n", "");
  expect_error(t, line_of(t, "[plant]"), "[plant] sensor_map", "missing key");
}

TEST(RigLoader, GenericPlantRefusesNanAndNegativeTimeConstants) {
  std::string t = generic_edit("coupling = [[2.0, -1.0]]", "coupling = [[2.0, nan]]");
  expect_error(t, line_of(t, "coupling"), "[plant] coupling[0][1]", "must be finite, not nan");
  t = generic_edit("sensor_map = [[1.0, 0.0, 0.5]]", "sensor_map = [[1.0, 0.0, 1e7]]");
  expect_error(t, line_of(t, "sensor_map"), "[plant] sensor_map[0][2]", "must be within +-1000000, not 10000000");
  t = generic_edit("tau = 0.05", "tau = -0.05");
  expect_error(t, line_of(t, "tau = -0.05"), "[[plant.actuator]] #1 tau",
               "must be in [0, 1000] s (a time constant), not -0.05");
  t = generic_edit("output_tau = [0.02]", "output_tau = [-1.0]");
  expect_error(t, line_of(t, "output_tau"), "[plant] output_tau[0]", "must be in [0, 1000], not -1");
  t = generic_edit("sensor_noise = [0.01]", "sensor_noise = [-0.01]");
  expect_error(t, line_of(t, "sensor_noise"), "[plant] sensor_noise[0]", "must be in [0, 1000000], not -0.01");
  t = generic_edit("gain = 3.0", "gain = inf");
  expect_error(t, line_of(t, "gain = inf"), "[[plant.actuator]] #1 gain", "must be finite, not inf");
  t = generic_edit("gain = 3.0", "gain = 0.0");
  expect_error(t, line_of(t, "gain = 0.0"), "[[plant.actuator]] #1 gain", "must not be 0");
}

TEST(RigLoader, GenericPlantActuatorsAreOnePerInputWithTheirShapesKeys) {
  std::string t = generic_edit("[[plant.actuator]]\nshape = \"power\"\nexponent = 2.0\n", "");
  expect_error(t, line_of(t, "[plant]"), "[plant] [[plant.actuator]]",
               "expected m = 2 tables (one per [[input]]), got 1");
  t = kGeneric + "\n[[plant.actuator]]\ngain = 1.0\n";
  expect_error(t, line_of(t, "[[plant.actuator]]", 3), "[[plant.actuator]] #3", "one more than the 2 [[input]] tables");
  t = generic_edit("knee = 0.2\n", "");
  expect_error(t, line_of(t, "[[plant.actuator]]"), "[[plant.actuator]] #1 knee", "missing key");
  t = generic_edit("exponent = 2.0", "knee = 2.0");
  expect_error(t, line_of(t, "knee = 2.0"), "[[plant.actuator]] #2 knee", "only for shape = \"tanh\" or \"saturation\"");
  t = generic_edit("exponent = 2.0", "exponent = 9.0");
  expect_error(t, line_of(t, "exponent = 9.0"), "[[plant.actuator]] #2 exponent", "must be in [0, 8], not 9");
  t = generic_edit("shape = \"tanh\"", "shape = \"cubic\"");
  expect_error(t, line_of(t, "shape = \"cubic\""), "[[plant.actuator]] #1 shape",
               "'cubic' is not one of: linear, tanh, saturation, power");
  t = generic_edit("play = 0.01", "play = 0.5");
  expect_error(t, line_of(t, "play = 0.5"), "[[plant.actuator]] #1 play", "must be < half the input's range, 0.5");
  t = generic_edit("tau = 0.05", "tua = 0.05");
  expect_error(t, line_of(t, "tua = 0.05"), "[[plant.actuator]] #1 tua", "unknown key (known: gain, shape, knee");
}

TEST(RigLoader, GenericKeysBelongToTheGenericKindAndItsRate) {
  std::string t = generic_edit("kind = \"generic\"", "kind = \"tendon\"");
  expect_error(t, line_of(t, "coupling"), "[plant] coupling", "only for kind = \"generic\"");
  // The largest rig a file may describe takes a generic plant too.
  std::string big = rig_of(8, 6, 32) + "\n[plant]\nkind = \"generic\"\ncoupling = [";
  for (int j = 0; j < 6; ++j) big += std::string(j ? ", " : "") + "[1, 1, 1, 1, 1, 1, 1, 1]";
  big += "]\nsensor_map = [";
  for (int k = 0; k < 32; ++k) big += std::string(k ? ", " : "") + "[0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0]";
  big += "]\n";
  for (int i = 0; i < 8; ++i) big += "[[plant.actuator]]\ntau = 0.1\n";
  const Rig r = parse_rig(big, "big.toml");
  EXPECT_EQ(generic_spec_problem(generic_plant_spec(r)), nullptr);
  EXPECT_EQ(generic_plant_spec(r).w, 32);
}

// [firmware] features: names of shared/firmware_features.hpp, each once,
// each one the rig's board can carry; the firmware's RigConfig carries them.
TEST(RigLoader, FirmwareFeaturesAreNamedServicesTheBoardCanCarry) {
  const Rig all = parse_rig(kBase, "probe.toml");
  EXPECT_EQ(all.firmware_features, kAllFirmwareFeatures);
  EXPECT_EQ(all.firmware_line, 0);
  EXPECT_EQ(firmware_rig(all).features, kAllFirmwareFeatures);

  const std::string some = std::string(kBase) + "\n[firmware]\nfeatures = [\"settings\", \"ident\"]\n";
  const Rig r = parse_rig(some, "probe.toml");
  EXPECT_EQ(r.firmware_features, feature::kSettings | feature::kIdent);
  EXPECT_EQ(r.firmware_line, line_of(some, "features"));
  EXPECT_EQ(firmware_rig(r).features, feature::kSettings | feature::kIdent);
  const std::string none = std::string(kBase) + "\n[firmware]\nfeatures = []\n";
  EXPECT_EQ(parse_rig(none, "probe.toml").firmware_features, 0u);

  std::string t = std::string(kBase) + "\n[firmware]\nfeatures = [\"ident\", \"telemetry\"]\n";
  expect_error(t, line_of(t, "features"), "[firmware] features[1]",
               "'telemetry' is not a service an image can leave out (known: \"ident\", \"model-upload\", "
               "\"table-upload\", \"settings\"; the link, parameters, runs on the compiled-in references and "
               "telemetry are always there)");
  t = std::string(kBase) + "\n[firmware]\nfeatures = [\"ident\", \"ident\"]\n";
  expect_error(t, line_of(t, "features"), "[firmware] features[1]", "'ident' is listed twice");
  t = std::string(kBase) + "\n[firmware]\nfeatures = \"ident\"\n";
  expect_error(t, line_of(t, "features"), "[firmware] features", "expected a list of services");
  t = std::string(kBase) + "\n[firmware]\nfeatures = [1]\n";
  expect_error(t, line_of(t, "features"), "[firmware] features[0]", "expected a service's name, got an integer");
  t = std::string(kBase) + "\n[firmware]\nfeature = []\n";
  expect_error(t, line_of(t, "feature = "), "[firmware] feature", "unknown key (known: features, optimize)");
  EXPECT_FALSE(all.firmware_size_first);
  EXPECT_TRUE(parse_rig(std::string(kBase) + "\n[firmware]\noptimize = \"size\"\n", "p.toml").firmware_size_first);
  EXPECT_FALSE(parse_rig(std::string(kBase) + "\n[firmware]\noptimize = \"speed\"\n", "p.toml").firmware_size_first);
  t = std::string(kBase) + "\n[firmware]\noptimize = \"small\"\n";
  expect_error(t, line_of(t, "optimize"), "[firmware] optimize", "'small' is not one of: speed, size");
}

TEST(RigLoader, SettingsOnABoardWithoutASettingsFlashAreRefusedAtTheirLine) {
  // mps2-an386's memory is RAM: its port keeps no settings. (Its inputs
  // have no PWM pin there.)
  const std::string shield = rig_text::replaced(rig_of(1, 1, 0), "pwm = \"PC6\"\n", "");
  const std::string t =
      "board = \"mps2-an386\"\n" + shield + "\n[firmware]\nfeatures = [\"ident\", \"settings\"]\n";
  expect_error(t, line_of(t, "features"), "[firmware] features[1]",
               "'settings': board mps2-an386 has nowhere to keep saved settings");
}

}  // namespace
}  // namespace nlsoft::host
