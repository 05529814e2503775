// The generator of an image's rig header (app/firmware/image_header.cpp):
// a rig file the test writes (3 inputs, 2 outputs, 5 sensors, 80 Hz) comes
// out as a header that says the rig's values, sizes the capacity from it,
// wires the file's pins, and compiles into the real image's main.cpp with
// arm-none-eabi-g++; rigs a board cannot take fail with file:line.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/files/cli_error.hpp"
#include "app/firmware/generated_text.hpp"
#include "app/firmware/image_header.hpp"
#include "support/text_checks.hpp"

namespace {

using nlsoft::test::contains;

using namespace nlsoft::console;
using nlsoft::host::CliError;
using nlsoft::host::RigError;
using nlsoft::host::parse_rig;

const char* kRig = R"(name = "gripper"
rate_hz = 80.0
nd = 2
dd = 2
board = "stm32f4"

[[input]]
name = "finger1"
min = 0.0
max = 2.0
neutral = 0.25
pwm = "PC6"

[[input]]
name = "finger2"
min = -1.0
max = 1.0
neutral = 0.0
pwm = "PB6"

[[input]]
name = "wrist"
min = 0.0
max = 1.0
neutral = 0.5

[[output]]
name = "x"
min = -10.0
max = 10.0

[[output]]
name = "y"
min = -5.0
max = 5.0

[[sensor]]
name = "s1"
source = "adc"
adc = 4
gain = 2.5
offset = -0.5

[[sensor]]
name = "s2"
source = "none"

[[sensor]]
name = "s3"
source = "adc"
adc = 0

[[sensor]]
name = "s4"
source = "adc"
adc = 13
gain = 0.1

[[sensor]]
name = "s5"
source = "none"

[controller]
Q = [10.0, 20.0]
Lambda = [1.0, 2.0, 3.0]
s = 1e-20
b = 1e-5
r = 400.0
N = 6
Nc = 2
eps = 0.0125

[model]
[[model.layer]]
kind = "gru"
units = 4

[[model.layer]]
kind = "dense"
units = 2
activation = "linear"
)";

std::string tmp_dir() {
  static const std::string dir = [] {
    std::string t = (std::filesystem::temp_directory_path() / "nlsoft-image-header-XXXXXX").string();
    if (!::mkdtemp(t.data())) std::abort();
    return t;
  }();
  return dir;
}

ImageSource source_of(const std::string& text, const std::string& board, const std::string& file = "gripper.toml") {
  ImageRequest q;
  q.board = board;
  return image_source(parse_rig(text, file), q);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

int line_of(const std::string& text, const std::string& needle, int nth = 1) {
  size_t at = std::string::npos;
  for (int i = 0; i < nth; ++i) at = text.find(needle, at == std::string::npos ? 0 : at + 1);
  int line = 1;
  for (size_t i = 0; i < at && at != std::string::npos; ++i) line += text[i] == '\n';
  return line;
}

TEST(ImageHeader, SpellsOutTheRigAndSizesTheCapacityFromIt) {
  const ImageSource s = source_of(kRig, "stm32f4");
  const std::string& h = s.header;
  EXPECT_TRUE(contains(h, "c.name = \"gripper\";")) << h;
  EXPECT_TRUE(contains(h, "c.platform = PlatformId(255);")) << h;  // no info_platform: Custom
  EXPECT_TRUE(contains(h, "c.m = 3, c.n = 2, c.w = 5, c.nd = 2, c.dd = 2;")) << h;
  EXPECT_TRUE(contains(h, "c.rate_hz = 80.0f;")) << h;
  EXPECT_TRUE(contains(h, "c.u_min[0] = 0.0f, c.u_max[0] = 2.0f, c.u_neutral[0] = 0.25f, c.Lambda[0] = 1.0f;")) << h;
  EXPECT_TRUE(contains(h, "c.u_min[2] = 0.0f, c.u_max[2] = 1.0f, c.u_neutral[2] = 0.5f, c.Lambda[2] = 3.0f;")) << h;
  EXPECT_TRUE(contains(h, "c.Q[1] = 20.0f;")) << h;
  EXPECT_TRUE(contains(h, "c.N = 6, c.N1 = 1, c.Nc = 2")) << h;
  EXPECT_TRUE(contains(h, "c.eps = 0.0125f")) << h;
  // The model's shape is the one kernel; the arrays are the rig's size.
  EXPECT_TRUE(contains(h, "using ImageShape = NetShape<3, 2, 5, 2, KindLayer<LayerKind::Gru, 4>, DenseLayer<2>>;")) << h;
  EXPECT_TRUE(contains(h, "static constexpr int m = 3, n = 2, w = 5, nd = 2;")) << h;
  EXPECT_TRUE(contains(h, "static constexpr int N = 6, Nc = 2;")) << h;
  EXPECT_TRUE(contains(h, "layers = 2;")) << h;
  // No [plant]: no HIL image, no Plant.
  EXPECT_FALSE(s.hil);
  EXPECT_FALSE(contains(h, "using Plant")) << h;
  EXPECT_EQ(cmake_bracket_value(s.cmake, "NLSOFT_IMAGE_RIG"), "gripper") << s.cmake;
  EXPECT_TRUE(contains(s.cmake, "set(NLSOFT_IMAGE_HIL 0)")) << s.cmake;
}

TEST(ImageHeader, WiresTheFilesPinsWithEachSensorsScaling) {
  const std::string h = source_of(kRig, "stm32f4").header;
  // Actuators by the board's rows (PC6 row 0, PB6 row 4); the wrist has no pin.
  EXPECT_TRUE(contains(h, "kPwm[0],  // finger1 on PC6")) << h;
  EXPECT_TRUE(contains(h, "kPwm[4],  // finger2 on PB6")) << h;
  EXPECT_TRUE(contains(h, "kNoPwm,  // wrist")) << h;
  // Sensors up to the last wired one (s4); ADC1_IN4 is the board's row 2, IN13 row 10.
  EXPECT_TRUE(contains(h, "constexpr int kRigAnalogueRows = 4;")) << h;
  EXPECT_TRUE(contains(h, "{kAnalogue[2].pin, kAnalogue[2].adc_channel, -0.5f, 2.5f},  // s1 on ADC1_IN4")) << h;
  EXPECT_TRUE(contains(h, "kNoAnalogue,  // s2")) << h;
  EXPECT_TRUE(contains(h, "{kAnalogue[0].pin, kAnalogue[0].adc_channel, 0.0f, 1.0f},  // s3 on ADC1_IN0")) << h;
  EXPECT_TRUE(contains(h, "{kAnalogue[10].pin, kAnalogue[10].adc_channel, 0.0f, 0.1f},  // s4 on ADC1_IN13")) << h;
  EXPECT_FALSE(contains(h, "kNoAnalogue,  // s5")) << h;  // past the last wired row
  EXPECT_TRUE(contains(h, "{SensorFrom::None, 0, 0, 1.0f, 0.0f},  // s5: not wired")) << h;
  // QEMU's board has no pins to wire.
  EXPECT_FALSE(contains(source_of(kRig, "mps2-an386").header, "kRigPwm"));
}

// The gripper with both outputs read on the board: a position sensor on
// ADC1_IN7 (x = 4 V^-1 * volts - 6.6 mm) and one on IN8.
std::string adc_outputs(const std::string& y_source = "source = \"adc\"\nadc = 8\n") {
  std::string text = replaced(kRig, "name = \"x\"\nmin = -10.0\nmax = 10.0\n",
                              "name = \"x\"\nmin = -10.0\nmax = 10.0\nsource = \"adc\"\nadc = 7\ngain = 4.0\n"
                              "offset = -6.6\n");
  return replaced(text, "name = \"y\"\nmin = -5.0\nmax = 5.0\n", "name = \"y\"\nmin = -5.0\nmax = 5.0\n" + y_source);
}

TEST(ImageHeader, ReadsTheOutputsOnTheAdcWhenEveryOutputIsWired) {
  const std::string h = source_of(adc_outputs(), "stm32f4").header;
  // ADC1_IN7 is the board's row 4, IN8 row 5; scaled as the file says, in output order.
  EXPECT_TRUE(contains(h, "constexpr int kRigOutputRows = 2;")) << h;
  EXPECT_TRUE(contains(h, "constexpr AnalogueInput kRigOutputAnalogue[2] = {\n"
                          "    {kAnalogue[4].pin, kAnalogue[4].adc_channel, -6.6f, 4.0f},  // x on ADC1_IN7\n"
                          "    {kAnalogue[5].pin, kAnalogue[5].adc_channel, 0.0f, 1.0f},  // y on ADC1_IN8\n};"))
      << h;
  // The sensors keep their rows.
  EXPECT_TRUE(contains(h, "constexpr int kRigAnalogueRows = 4;")) << h;
  // One output read elsewhere: y is every output or none, so the board reads none and says which it leaves.
  const std::string mixed = source_of(adc_outputs("source = \"external\"\n"), "stm32f4").header;
  EXPECT_TRUE(contains(mixed, "constexpr int kRigOutputRows = 0;")) << mixed;
  EXPECT_TRUE(contains(mixed, "    kNoAnalogue,  // x not read: not every output is source = \"adc\"\n")) << mixed;
  EXPECT_FALSE(contains(mixed, "ADC1_IN7")) << mixed;
  EXPECT_EQ(source_of(adc_outputs("source = \"external\"\n"), "stm32f4").note,
            "output x on ADC1 not read: the image reads the outputs only when every one has source = \"adc\", so it "
            "measures no y (no y_true)");
  EXPECT_EQ(source_of(adc_outputs(), "stm32f4").note, "");
  // No output on the ADC (the gripper as written): none read.
  const std::string none = source_of(kRig, "stm32f4").header;
  EXPECT_TRUE(contains(none, "constexpr int kRigOutputRows = 0;")) << none;
  EXPECT_TRUE(contains(none, "    kNoAnalogue,  // no output is read on the board\n")) << none;
}

TEST(ImageHeader, ANamedPlantMakesTheHilImage) {
  // A 2-input, 3-output, 11-sensor rig is tendon's plant's size.
  std::ifstream in(NLSOFT_SOURCE_DIR "/rigs/tendon.toml");
  std::string tendon((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const ImageSource s = source_of(replaced(tendon, "name = \"tendon\"", "name = \"bender\""), "stm32f4", "b.toml");
  EXPECT_TRUE(s.hil);
  EXPECT_TRUE(contains(s.header, "#include \"shared/plant_tendon.hpp\"")) << s.header;
  EXPECT_TRUE(contains(s.header, "using Plant = TendonPlant;")) << s.header;
  EXPECT_TRUE(contains(s.cmake, "set(NLSOFT_IMAGE_HIL 1)")) << s.cmake;
}

// The gripper with a generic plant: a tanh, a square law with backlash and
// a hard stop, coupled into both outputs, read by five sensors.
const char* kGenericPlant = R"(
[plant]
kind = "generic"
coupling = [[3.0, 1.0, -0.5],
            [-0.5, 1.5, 2.0]]
output_offset = [0.5, -1.0]
output_tau = [0.0, 0.03]
sensor_map = [[1.0, 0.0, 0.0, 0.0, 0.0],
              [0.0, 1.0, 0.0, 0.0, 0.0],
              [0.0, 0.0, 1.0, 0.0, 0.0],
              [0.0, 0.0, 0.5, 1.0, 0.0],
              [0.2, 0.0, 0.0, 0.0, 1.0]]
sensor_offset = [0.0, 0.0, 0.0, 0.0, 0.25]
sensor_noise = [0.01, 0.01, 0.01, 0.01, 0.02]

[[plant.actuator]]
gain = 8.0
shape = "tanh"
knee = 0.4
tau = 0.06

[[plant.actuator]]
gain = 4.0
shape = "power"
exponent = 2.0
play = 0.02
tau = 0.08

[[plant.actuator]]
gain = 3.0
shape = "saturation"
knee = 0.6
tau = 0.05
)";

TEST(ImageHeader, AGenericPlantIsItsSpecInFlashAndMakesTheHilImage) {
  const ImageSource s = source_of(std::string(kRig) + kGenericPlant, "mps2-an386");
  const std::string& h = s.header;
  EXPECT_TRUE(s.hil);
  EXPECT_TRUE(contains(s.cmake, "set(NLSOFT_IMAGE_HIL 1)")) << s.cmake;
  EXPECT_TRUE(contains(h, "#include \"shared/plant_generic.hpp\"")) << h;
  EXPECT_TRUE(contains(h, "s.m = 3, s.n = 2, s.w = 5;\n  s.dt = 0.0125f;")) << h;
  // Each input's limits are the [[input]]'s, its statics the actuator's.
  EXPECT_TRUE(contains(h, "s.input[0] = {0.0f, 2.0f, 0.25f, 8.0f, GenericShape::Tanh, 0.4f,")) << h;
  EXPECT_TRUE(contains(h, "s.input[1] = {-1.0f, 1.0f, 0.0f, 4.0f, GenericShape::Power,")) << h;
  EXPECT_TRUE(contains(h, ", 2.0f, 0.02f, 0.08f};  // finger2")) << h;
  EXPECT_TRUE(contains(h, "s.input[2] = {0.0f, 1.0f, 0.5f, 3.0f, GenericShape::Saturation, 0.6f,")) << h;
  // The outputs' box is the [[output]]'s range; B and C row by row.
  EXPECT_TRUE(contains(h, "s.output[0] = {-10.0f, 10.0f, 0.5f, 0.0f};  // x")) << h;
  EXPECT_TRUE(contains(h, "s.output[1] = {-5.0f, 5.0f, -1.0f, 0.03f};  // y")) << h;
  EXPECT_TRUE(contains(h, "s.B[1][0] = -0.5f, s.B[1][1] = 1.5f, s.B[1][2] = 2.0f;")) << h;
  EXPECT_TRUE(contains(h, "s.sensor[4] = {0.25f, 0.02f};  // s5")) << h;
  EXPECT_TRUE(contains(h, "s.C[4][0] = 0.2f, s.C[4][1] = 0.0f, s.C[4][2] = 0.0f, s.C[4][3] = 0.0f, "
                          "s.C[4][4] = 1.0f;")) << h;
  EXPECT_TRUE(contains(h, "inline constexpr GenericPlantSpec kPlantSpec = image_plant_spec();")) << h;
  EXPECT_TRUE(contains(h, "using Plant = FixedGenericPlant<kPlantSpec>;")) << h;
}

TEST(ImageHeader, MoreActuatorsThanThePwmRowsIsOneErrorAtTheInput) {
  std::string text = kRig;
  const std::string extra = "\n[[input]]\nname = \"more{}\"\nmin = 0.0\nmax = 1.0\nneutral = 0.5\n";
  std::string lambda = "Lambda = [1.0, 2.0, 3.0";
  for (int i = 4; i <= 7; ++i) {
    std::string block = extra;
    block.replace(block.find("{}"), 2, std::to_string(i));
    text = replaced(text, "\n[[output]]", block + "\n[[output]]");
    lambda += ", 1.0";
  }
  text = replaced(text, "Lambda = [1.0, 2.0, 3.0", lambda);
  // Loads (a rig may have 8 inputs), but the Nucleo drives 6 PWM outputs.
  try {
    source_of(text, "stm32f4", "big.toml");
    FAIL() << "a 7-input rig built for stm32f4";
  } catch (const RigError& e) {
    const std::string want = "big.toml:" + std::to_string(line_of(text, "[[input]]", 7)) + ": [[input]] #7: board "
                             "stm32f4 drives 6 PWM outputs (PC6, PC7, PC8, PC9, PB6, PB7); this rig has 7 inputs";
    EXPECT_EQ(e.what(), want);
  }
  // QEMU's board drives nothing: the same rig builds for it.
  EXPECT_NO_THROW(source_of(text, "mps2-an386", "big.toml"));
}

TEST(ImageHeader, AnUnknownPinIsOneErrorAtItsLine) {
  const std::string text = replaced(kRig, "pwm = \"PB6\"", "pwm = \"PA9\"");
  try {
    source_of(text, "stm32f4", "pins.toml");
    FAIL() << "PA9 accepted";
  } catch (const RigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("pins.toml:" + std::to_string(line_of(text, "PA9")) + ": [[input]] #2 pwm: "
                                          "unknown pin 'PA9' on board stm32f4",
                                          0),
              0u)
        << e.what();
  }
}

TEST(ImageHeader, ARigWithoutAShapeOrWithAnotherHistoryIsRefused) {
  const std::string no_model = std::string(kRig).substr(0, std::string(kRig).find("[model]"));
  EXPECT_THROW(source_of(no_model, "mps2-an386"), RigError);
  ImageRequest q;
  q.board = "teensy";
  EXPECT_THROW(image_source(parse_rig(kRig, "g.toml"), q), CliError);
}

// The gripper with s2 a magnetometer's z on I2C and s5 a pressure in kPa
// from a DPS310.
std::string with_devices() {
  std::string t = replaced(kRig, "[[sensor]]\nname = \"s1\"",
                           "[[device]]\nname = \"palm\"\nchip = \"lsm303dlhc_mag\"\nbus = \"i2c1\"\naddress = 0x1e\n"
                           "range = 8.1\nrate_hz = 220\n\n[[device]]\nname = \"air\"\nchip = \"dps310\"\nbus = \"i2c1\"\n"
                           "rate_hz = 32\n\n[[sensor]]\nname = \"s1\"");
  t = replaced(t, "name = \"s2\"\nsource = \"none\"", "name = \"s2\"\nsource = \"device\"\ndevice = \"palm\"\nchannel = \"z\"");
  return replaced(t, "name = \"s5\"\nsource = \"none\"",
                  "name = \"s5\"\nsource = \"device\"\ndevice = \"air\"\nchannel = \"pressure\"\ngain = 0.001");
}

TEST(ImageHeader, ListsEachDeviceAndWhereEachSensorIsRead) {
  {
    const std::string h = source_of(with_devices(), "stm32f4").header;
    EXPECT_TRUE(contains(h, "constexpr int kRigDeviceCount = 2;")) << h;
    // lsm303dlhc_mag is the catalog's row 1, dps310 row 2; GN 111 (±8.1 gauss), DO 111 (220 Hz); PM_RATE 32/s.
    EXPECT_TRUE(contains(h, "    {\"palm\", chips::kCatalog[1], 0, BusKind::I2c, 0x1e, 0, 100000u, {8.1f, 0xe0}, {220.0f, 0x1c}},"
                            "  // lsm303dlhc_mag on i2c1 at 0x1e, 100000 Hz clock, range 8.1 gauss, 220 Hz\n"))
        << h;
    EXPECT_TRUE(contains(h, "    {\"air\", chips::kCatalog[2], 0, BusKind::I2c, 0x77, 0, 100000u, {0.0f, 0x00}, {32.0f, 0x50}},"))
        << h;
    EXPECT_TRUE(contains(h, "static_assert(chips::same_name(kRigDevices[1].chip->name, \"dps310\"), \"the catalog's row\");"))
        << h;
    EXPECT_TRUE(contains(h, "constexpr RigSensorSource kRigSensorSources[5] = {\n"
                            "    {SensorFrom::Analogue, 0, 0, 2.5f, -0.5f},  // s1: ADC1_IN4\n"
                            "    {SensorFrom::Device, 0, 2, 1.0f, 0.0f},  // s2: palm's z\n"))
        << h;
    EXPECT_TRUE(contains(h, "    {SensorFrom::Device, 1, 0, 0.001f, 0.0f},  // s5: air's pressure\n};")) << h;
  }
  // Chips are on the file's board's buses: another board's image refuses them at the first.
  try {
    source_of(with_devices(), "mps2-an386");
    ADD_FAILURE() << "an image for another board took the chips";
  } catch (const RigError& e) {
    EXPECT_EQ(e.line, line_of(with_devices(), "[[device]]"));
    EXPECT_TRUE(contains(e.what(), "device 'palm' is on bus i2c1 of board stm32f4: build the image for stm32f4, not "
                                   "mps2-an386"))
        << e.what();
  }
  // Without devices the tables are there, empty, for the port to compile against.
  EXPECT_TRUE(contains(source_of(kRig, "mps2-an386").header, "constexpr int kRigDeviceCount = 0;"));
  EXPECT_TRUE(contains(source_of(kRig, "mps2-an386").header, "    {SensorFrom::None, 0, 0, 1.0f, 0.0f},  // s2: not wired\n"));
}

ImageSource images_of(const std::string& text, const std::string& board, ImageKinds kinds) {
  ImageRequest q;
  q.board = board;
  q.images = kinds;
  return image_source(parse_rig(text, "g.toml"), q);
}

// A board image reads the chips, so only the rig's board builds it; a HIL
// image reads none, so any board does. Runnable asks each board for what it
// can run and says when that is the HIL image alone.
TEST(ImageHeader, EachBoardGetsTheImagesItCanRun) {
  const std::string chips_plant = with_devices() + kGenericPlant;
  const std::string elsewhere = "rig 'gripper' on mps2-an386: the HIL image only (its chips are on board stm32f4's buses)";
  const struct {
    const char* board;
    ImageKinds kinds;
    bool board_image;
    std::string note, header_line;
  } cases[] = {
      {"stm32f4", ImageKinds::Runnable, true, "", "// For the board image and the HIL image.\n"},
      {"mps2-an386", ImageKinds::Runnable, false, elsewhere,
       "// For the HIL image only, in which the simulated plant gives every sensor channel (its chips are on board "
       "stm32f4's buses).\n"},
      // Asked for explicitly, the HIL image alone is what was asked: nothing to explain.
      {"mps2-an386", ImageKinds::Hil, false, "",
       "// For the HIL image only, in which the simulated plant gives every sensor channel.\n"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(std::string(c.board) + " " + image_kinds_name(c.kinds));
    const ImageSource s = images_of(chips_plant, c.board, c.kinds);
    EXPECT_EQ(s.board, c.board_image);
    EXPECT_TRUE(s.hil);
    EXPECT_EQ(s.note, c.note);
    EXPECT_TRUE(contains(s.header, c.header_line)) << s.header;
    EXPECT_TRUE(contains(s.cmake, fmt::format("set(NLSOFT_IMAGE_BOARD {})\nset(NLSOFT_IMAGE_HIL 1)\n", int(c.board_image))))
        << s.cmake;
    // The build log's line: the reason a board gets the HIL image only, else nothing.
    EXPECT_EQ(cmake_bracket_value(s.cmake, "NLSOFT_IMAGE_NOTE"), c.board_image ? "" : c.note) << s.cmake;
  }
  // Without chips every board runs both.
  for (const char* board : {"mps2-an386", "stm32f4"}) {
    const ImageSource s = images_of(std::string(kRig) + kGenericPlant, board, ImageKinds::Runnable);
    EXPECT_TRUE(s.board) << board;
    EXPECT_TRUE(s.hil) << board;
  }
  // The board image alone: no HIL image even with a plant.
  EXPECT_FALSE(images_of(chips_plant, "stm32f4", ImageKinds::Board).hil);
  // Refused: the board image on another board, whether asked for alone or with the HIL one.
  for (ImageKinds k : {ImageKinds::Both, ImageKinds::Board}) {
    try {
      images_of(chips_plant, "mps2-an386", k);
      ADD_FAILURE() << image_kinds_name(k) << ": the board image of another board's chips";
    } catch (const RigError& e) {
      EXPECT_EQ(e.line, line_of(chips_plant, "[[device]]"));
      EXPECT_TRUE(contains(e.what(), "build the image for stm32f4, not mps2-an386 (a HIL image, which reads no chip, "
                                     "builds for any board)"))
          << e.what();
    }
  }
  // Refused: a HIL image without a plant; on another board then nothing is runnable, and it is said.
  try {
    images_of(with_devices(), "stm32f4", ImageKinds::Hil);
    ADD_FAILURE() << "a HIL image without a plant";
  } catch (const RigError& e) {
    EXPECT_TRUE(contains(e.what(), "g.toml:1: [plant]: no [plant]: there is no HIL image to build")) << e.what();
  }
  try {
    images_of(with_devices(), "mps2-an386", ImageKinds::Runnable);
    ADD_FAILURE() << "a runnable image of chips elsewhere without a plant";
  } catch (const RigError& e) {
    EXPECT_TRUE(contains(e.what(), "board mps2-an386 can run no image of this rig (its chips are on board stm32f4's "
                                   "buses, and a HIL image needs a simulated plant)"))
        << e.what();
  }
}

TEST(ImageHeader, ImageKindsAreFourWordsAndNoOther) {
  for (ImageKinds k : {ImageKinds::Both, ImageKinds::Board, ImageKinds::Hil, ImageKinds::Runnable})
    EXPECT_EQ(parse_image_kinds(image_kinds_name(k), "--images"), k);
  try {
    parse_image_kinds("all", "--images");
    ADD_FAILURE() << "took 'all'";
  } catch (const CliError& e) {
    EXPECT_STREQ(e.what(), "--images all: one of both, board, hil, runnable");
  }
}

// [firmware] features travel in the RigConfig; a service the rig file asks
// for that the board's port cannot carry is refused at the list's line.
TEST(ImageHeader, FirmwareFeaturesAreWrittenAndABoardThatLacksOneRefusesIt) {
  EXPECT_TRUE(contains(source_of(kRig, "stm32f4").header,
                       "c.features = 0xfu;  // [firmware] features: ident, model-upload, table-upload, settings"));
  const std::string none = std::string(kRig) + "\n[firmware]\nfeatures = []\n";
  EXPECT_TRUE(contains(source_of(none, "mps2-an386").header,
                       "c.features = 0x0u;  // [firmware] features: none beyond the minimum"));
  // The rig's own board (stm32f4) keeps settings; mps2-an386 has nowhere to.
  const std::string with = std::string(kRig) + "\n[firmware]\nfeatures = [\"settings\"]\n";
  EXPECT_NO_THROW(source_of(with, "stm32f4"));
  try {
    source_of(with, "mps2-an386");
    ADD_FAILURE() << "mps2-an386 took settings";
  } catch (const RigError& e) {
    EXPECT_EQ(e.line, line_of(with, "features"));
    EXPECT_TRUE(contains(e.what(), "[firmware] features: 'settings': board mps2-an386 has nowhere to keep saved "
                                   "settings (no settings flash: its port keeps none); leave it out, or build for a "
                                   "board that has it"))
        << e.what();
  }
  // Without the list, every board builds what it can carry.
  EXPECT_NO_THROW(source_of(kRig, "mps2-an386"));
}

// An image that takes no model upload runs the model it is built with: its
// Dense layers' activations are compiled into the shape (net_shape.hpp), a
// GRU's stay the model's; with uploads every activation is the model's.
TEST(ImageHeader, AnImageWithoutModelUploadsFixesItsDenseActivations) {
  EXPECT_TRUE(contains(source_of(kRig, "stm32f4").header,
                       "using ImageShape = NetShape<3, 2, 5, 2, KindLayer<LayerKind::Gru, 4>, DenseLayer<2>>;"));
  const std::string h = source_of(std::string(kRig) + "\n[firmware]\nfeatures = [\"ident\"]\n", "stm32f4").header;
  EXPECT_TRUE(contains(h, "// No model uploads: the Dense layers' activations are the built-in model's, compiled in.\n"
                          "using ImageShape = NetShape<3, 2, 5, 2, KindLayer<LayerKind::Gru, 4>, DenseLayer<2, int(Activation::Linear)>>;"))
      << h;
  const std::string uploads =
      source_of(std::string(kRig) + "\n[firmware]\nfeatures = [\"model-upload\"]\n", "stm32f4").header;
  EXPECT_TRUE(contains(uploads, "using ImageShape = NetShape<3, 2, 5, 2, KindLayer<LayerKind::Gru, 4>, DenseLayer<2>>;")) << uploads;
}

// [firmware] optimize = "size": the generic kernel instead of the shape's,
// and the image compiled with NLSOFT_SIZE_FIRST; "speed" (the default) as before.
TEST(ImageHeader, ASizeFirstImageHasTheGenericKernelAndItsDefinition) {
  const ImageSource speed = source_of(kRig, "stm32f4");
  EXPECT_TRUE(contains(speed.header, "using Shapes = ShapeList<ImageShape>;\n  static constexpr bool generic = false;"));
  EXPECT_TRUE(contains(speed.cmake, "set(NLSOFT_IMAGE_DEFINITIONS \"\")"));
  const ImageSource size = source_of(std::string(kRig) + "\n[firmware]\noptimize = \"size\"\n", "stm32f4");
  EXPECT_TRUE(contains(size.header, "using Shapes = ShapeList<>;\n  static constexpr bool generic = true;"));
  EXPECT_TRUE(contains(size.cmake, "set(NLSOFT_IMAGE_DEFINITIONS NLSOFT_SIZE_FIRST=1)"));
}

TEST(ImageHeader, AHeaderWithoutABoardRefusesDevices) {
  const std::string t = with_devices();
  ImageRequest q;
  q.board = kPortableBoard;
  try {
    image_source(parse_rig(t, "g.toml"), q);
    ADD_FAILURE() << "a portable header took devices";
  } catch (const RigError& e) {
    EXPECT_EQ(e.line, line_of(t, "[[device]]"));
    EXPECT_TRUE(contains(e.what(), "[[device]] #1: a header without a board has no bus drivers for device 'palm'"))
        << e.what();
  }
  q.board = kPortableBoard;
  EXPECT_NO_THROW(image_source(parse_rig(kRig, "g.toml"), q));
}

// Compiles `checks` (main.cpp with the rig header of `header_dir` and the
// port's rig HAL, then static_asserts) for the Cortex-M4F with the images'
// warnings as errors, in `dir`; the compiler's messages, or "" when it passed.
std::string m4_compile_errors(const std::string& dir, const std::string& header_dir, const std::string& port,
                              const std::string& checks) {
  std::ofstream(dir + "/check.cpp") << "#define NLSOFT_HIL 0\n#define NLSOFT_FIRMWARE_NAME \"nlsoft-test\"\n"
                                       "#define NLSOFT_HAVE_MODEL 0\n#include \"firmware/ports/cortex-m/main.cpp\"\n"
                                    << checks;
  std::string flags;
  std::ifstream warnings(NLSOFT_SOURCE_DIR "/cmake/warning_flags.txt");
  for (std::string w; std::getline(warnings, w);)
    if (!w.empty() && w[0] == '-') flags += " " + w;
  const std::string cmd = "arm-none-eabi-g++ -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -Os -std=c++17 "
                          "-fno-exceptions -fno-rtti -Werror" + flags + " -I" + header_dir + " -I" NLSOFT_SOURCE_DIR
                          "/firmware/ports/" + port + " -I" NLSOFT_SOURCE_DIR " -c " + dir + "/check.cpp -o " + dir +
                          "/check.o 2>" + dir + "/cc.log";
  const int rc = std::system(cmd.c_str());
  std::ifstream log(dir + "/cc.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  return rc == 0 ? "" : text.empty() ? "the compiler failed" : text;
}

// The header compiled where it goes: the real image's main.cpp with the
// stm32f4 rig HAL, for the Cortex-M4F, with the images' warnings as errors.
TEST(ImageHeader, CompilesIntoTheStm32f4ImageForCortexM4) {
  if (std::system("command -v arm-none-eabi-g++ >/dev/null 2>&1") != 0) GTEST_SKIP() << "no arm-none-eabi-g++";
  const std::string dir = tmp_dir() + "/gripper";
  write_image_source(source_of(kRig, "stm32f4"), dir);
  // The HAL's own view of the pins: actuator 3 undriven, two scanned sensors then one more.
  std::ofstream(tmp_dir() + "/check.cpp") << R"(#define NLSOFT_HIL 0
#define NLSOFT_FIRMWARE_NAME "nlsoft-test"
#define NLSOFT_HAVE_MODEL 0
#include "firmware/ports/cortex-m/main.cpp"
static_assert(nlsoft::fw::cortex_m::kRig.m == 3 && nlsoft::fw::cortex_m::Cap::w == 5, "the rig's size");
static_assert(nlsoft::fw::stm32f4::kRigPwm[2].timer == 0, "the wrist is not driven");
static_assert(nlsoft::fw::cortex_m::kRig.rate_hz == 80.0f, "80 Hz");
static_assert(!PortHal::kMeasuresOutput, "no output on the ADC: y is not measured");
)";
  std::string flags;
  std::ifstream warnings(NLSOFT_SOURCE_DIR "/cmake/warning_flags.txt");
  for (std::string w; std::getline(warnings, w);)
    if (!w.empty() && w[0] == '-') flags += " " + w;
  const std::string cmd = "arm-none-eabi-g++ -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -Os -std=c++17 "
                          "-fno-exceptions -fno-rtti -Werror" + flags + " -I" + dir + " -I" NLSOFT_SOURCE_DIR
                          "/firmware/ports/stm32f4 -I" NLSOFT_SOURCE_DIR " -c " + tmp_dir() + "/check.cpp -o " +
                          tmp_dir() + "/check.o 2>" + tmp_dir() + "/cc.log";
  const int rc = std::system(cmd.c_str());
  std::ifstream log(tmp_dir() + "/cc.log");
  std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_EQ(rc, 0) << text;
}

// Sensor chips compiled where they go: the stm32f4 HAL builds a driver per
// device over its bus masters and hands the firmware their sampler.
TEST(ImageHeader, ChipsCompileIntoTheStm32f4ImageThatSamplesThem) {
  if (std::system("command -v arm-none-eabi-g++ >/dev/null 2>&1") != 0) GTEST_SKIP() << "no arm-none-eabi-g++";
  const std::string dir = tmp_dir() + "/chips";
  write_image_source(source_of(with_devices(), "stm32f4"), dir + "/gripper");
  EXPECT_EQ(m4_compile_errors(dir, dir + "/gripper", "stm32f4",
                              "static_assert(nlsoft::fw::cortex_m::kRigDeviceCount == 2, \"two chips\");\n"
                              "static_assert(nlsoft::fw::cortex_m::kRigDevices[1].chip == &nlsoft::chips::kDps310, "
                              "\"the second a DPS310\");\n"),
            "");
}

// The outputs on the ADC compiled where they go: the HAL scans them after
// the sensors and the image says it measures y.
TEST(ImageHeader, ReadOutputsCompileIntoTheStm32f4ImageThatMeasuresY) {
  if (std::system("command -v arm-none-eabi-g++ >/dev/null 2>&1") != 0) GTEST_SKIP() << "no arm-none-eabi-g++";
  const std::string dir = tmp_dir() + "/measured";
  write_image_source(source_of(adc_outputs(), "stm32f4"), dir + "/gripper");
  EXPECT_EQ(m4_compile_errors(dir, dir + "/gripper", "stm32f4",
                              "static_assert(PortHal::kMeasuresOutput, \"every output on the ADC: y is measured\");\n"
                              "static_assert(nlsoft::fw::stm32f4::kRigOutputAnalogue[1].adc_channel == 8, "
                              "\"y on ADC1_IN8\");\n"),
            "");
}

// The generic plant's HIL image compiled where it goes: the real main.cpp
// with HilHal<Plant>, for both boards; the spec checked at compile time.
TEST(ImageHeader, AGenericPlantsHilImageCompilesForCortexM4) {
  if (std::system("command -v arm-none-eabi-g++ >/dev/null 2>&1") != 0) GTEST_SKIP() << "no arm-none-eabi-g++";
  std::string flags;
  std::ifstream warnings(NLSOFT_SOURCE_DIR "/cmake/warning_flags.txt");
  for (std::string w; std::getline(warnings, w);)
    if (!w.empty() && w[0] == '-') flags += " " + w;
  // With chips too: on mps2-an386 their header is for the HIL image only,
  // whose device table names the other board's buses and is never built.
  using Case = std::pair<const char*, bool>;
  for (const auto& [board, chips] : {Case{"mps2-an386", false}, Case{"stm32f4", false}, Case{"mps2-an386", true}}) {
    SCOPED_TRACE(std::string(board) + (chips ? " with chips" : ""));
    const std::string dir = tmp_dir() + "/generic-" + board + (chips ? "-chips" : "");
    write_image_source(images_of((chips ? with_devices() : std::string(kRig)) + kGenericPlant, board,
                                 ImageKinds::Runnable),
                       dir + "/gripper");
    std::ofstream(dir + "/check.cpp") << R"(#define NLSOFT_HIL 1
#define NLSOFT_FIRMWARE_NAME "nlsoft-test"
#define NLSOFT_HAVE_MODEL 0
#include "firmware/ports/cortex-m/main.cpp"
namespace cm = nlsoft::fw::cortex_m;
static_assert(cm::Plant::m == 3 && cm::Plant::n == 2 && cm::Plant::w == 5, "the rig's size");
static_assert(cm::kPlantSpec.B[0][2] == -0.5f && cm::kPlantSpec.C[3][2] == 0.5f, "the file's coupling and map");
static_assert(cm::kPlantSpec.input[1].shape == nlsoft::GenericShape::Power, "b's square law");
static_assert(cm::Plant::kDt == 0.0125f, "80 Hz");
)";
    const std::string cmd = "arm-none-eabi-g++ -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard -Os "
                            "-std=c++17 -fno-exceptions -fno-rtti -Werror" + flags + " -I" + dir + "/gripper -I"
                            NLSOFT_SOURCE_DIR "/firmware/ports/" + board + " -I" NLSOFT_SOURCE_DIR " -c " + dir +
                            "/check.cpp -o " + dir + "/check.o 2>" + dir + "/cc.log";
    const int rc = std::system(cmd.c_str());
    std::ifstream log(dir + "/cc.log");
    std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
    EXPECT_EQ(rc, 0) << text;
  }
}

// A C++ string literal read back as the compiler reads one (the escapes
// cpp_string_literal writes: \ooo and a backslash before a character).
std::string read_literal(const std::string& text, size_t at) {
  std::string out;
  EXPECT_EQ(text[at], '"');
  for (size_t i = at + 1; i < text.size() && text[i] != '"'; ++i) {
    if (text[i] != '\\') {
      out += text[i];
    } else if (text[i + 1] >= '0' && text[i + 1] <= '7') {
      out += char(std::stoi(text.substr(i + 1, 3), nullptr, 8));
      i += 3;
    } else {
      out += text[++i];
    }
  }
  return out;
}

const std::string kHostile =
    "q\"b\\s\n#include \"/etc/hostname\"\r\n#error x $(touch PWNED) `id` */ \") ]] ]=] ?\?/ \xc3\xa9\x7f\x01";

// Whatever a path holds stays a string in the header: on the first line,
// inside one literal that reads back as the path.
TEST(ImageHeader, ARigFilesPathIsOneStringLiteral) {
  const std::string h = source_of(kRig, "mps2-an386", kHostile + ".toml").header;
  const std::string first = h.substr(0, h.find('\n'));
  EXPECT_TRUE(contains(first, "(rig 'gripper', CRC-32 0x")) << first;
  EXPECT_EQ(read_literal(first, first.find('"')), kHostile + ".toml") << first;
  EXPECT_FALSE(contains(h, "\n#include \"/etc/hostname\"")) << h;
  EXPECT_FALSE(contains(h, "\n#error")) << h;
}

TEST(GeneratedText, EveryByteReadsBack) {
  std::string every;
  for (int c = 1; c < 256; ++c) every += char(c);
  for (const std::string& text : {kHostile, every, std::string(), std::string("\n\nstarts with newlines")}) {
    const std::string lit = cpp_string_literal(text);
    EXPECT_EQ(lit.find('\n'), std::string::npos);
    EXPECT_EQ(read_literal(lit, 0), text);
    // A CMake bracket argument: closed only where it ends, whatever '=' the text holds.
    const std::string cmake = "set(A " + cmake_bracket(text) + ")\nset(B " + cmake_bracket("b") + ")\n";
    EXPECT_EQ(cmake_bracket_value(cmake, "A"), text) << cmake;
    EXPECT_EQ(cmake_bracket_value(cmake, "B"), "b") << cmake;
  }
  EXPECT_EQ(cmake_bracket("a]]b]=]c"), "[==[\na]]b]=]c]==]");
  EXPECT_EQ(cmake_bracket_value("set(A \"x\")\n", "A"), std::nullopt);
}

}  // namespace
