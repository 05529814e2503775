// The board table (host/rig/board_table.hpp): the one place a board is
// described, what the console derives from it for the boards it had before
// (the same QEMU command lines and image names), the refusals of a board
// that is none or cannot do what is asked, and the other lists of boards
// (the firmware build's, the tools', the bash completion's) held equal to it.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "host/files/cli_error.hpp"
#include "host/rig/board_pins.hpp"
#include "host/rig/board_table.hpp"

namespace nlsoft::host {
namespace {

using Words = std::vector<std::string>;

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Words split(const std::string& text, char sep) {
  Words out;
  std::stringstream s(text);
  for (std::string w; std::getline(s, w, sep);)
    if (!w.empty()) out.push_back(w);
  return out;
}

TEST(BoardTable, NamesTheBoardsAndTheirImagesOnce) {
  std::set<std::string> names, folders, prefixes;
  for (const Board& b : boards()) {
    EXPECT_FALSE(b.cpu.empty()) << b.name;
    EXPECT_FALSE(b.description.empty()) << b.name;
    EXPECT_TRUE(names.insert(b.name).second) << b.name << " twice";
    EXPECT_TRUE(folders.insert(b.image_folder).second) << b.image_folder << " twice";
    EXPECT_TRUE(prefixes.insert(b.image_prefix).second) << b.image_prefix << " twice";
    EXPECT_EQ(board_named(b.name), &b);
    // Every board a rig file may name has its pins and buses.
    ASSERT_NE(find_board(b.name), nullptr) << b.name;
  }
  EXPECT_EQ(image_board_names(), (Words{"mps2-an386", "stm32f4", "mps2-an500", "mps2-an385"}));
  EXPECT_EQ(shipped_board_names(), (Words{"mps2-an386", "stm32f4", "mps2-an500"}));
  EXPECT_EQ(qemu_board_names(), (Words{"mps2-an386", "stm32f4", "mps2-an500", "mps2-an385"}));
  EXPECT_EQ(flash_board_names(), (Words{"stm32f4"}));
  EXPECT_EQ(board_named("mps2-an500")->cpu, "Cortex-M7");
  EXPECT_EQ(board_named("mps2-an386")->cpu, "Cortex-M4F");
  EXPECT_EQ(board_named("nucleo"), nullptr);
  EXPECT_EQ(std::string(kDefaultQemuBoard), "mps2-an386");
}

TEST(BoardTable, GivesTheCommandLinesAndImageNamesTheConsoleSpeltBefore) {
  EXPECT_EQ(qemu_machine_args(*board_named("mps2-an386"), "a.elf"),
            (Words{"-M", "mps2-an386", "-serial", "pty", "-kernel", "a.elf"}));
  EXPECT_EQ(qemu_machine_args(*board_named("stm32f4"), "a.elf"),
            (Words{"-M", "netduinoplus2", "-serial", "null", "-serial", "pty", "-kernel", "a.elf"}));
  EXPECT_EQ(qemu_machine_args(*board_named("mps2-an500"), "a.elf"),
            (Words{"-M", "mps2-an500", "-serial", "pty", "-kernel", "a.elf"}));
  EXPECT_EQ(qemu_machine_args(*board_named("mps2-an385"), "a.elf"),
            (Words{"-M", "mps2-an385", "-serial", "pty", "-kernel", "a.elf"}));
  EXPECT_EQ(shipped_image(*board_named("mps2-an386"), "hasel", true), "m4/nlsoft-m4-hasel-hil.elf");
  EXPECT_EQ(shipped_image(*board_named("stm32f4"), "tendon", false), "stm32f4/nlsoft-stm32f4-tendon.elf");
  EXPECT_EQ(shipped_image(*board_named("mps2-an500"), "msd", true), "m7/nlsoft-m7-msd-hil.elf");
  EXPECT_EQ(board_named("stm32f4")->openocd_config, "board/st_nucleo_f4.cfg");
}

TEST(BoardTable, TheMps2BoardsShareTheShieldBuses) {
  const BoardPins* an386 = find_board("mps2-an386");
  const BoardPins* an500 = find_board("mps2-an500");
  ASSERT_TRUE(an386 && an500);
  ASSERT_EQ(an386->buses.size(), an500->buses.size());
  for (size_t i = 0; i < an386->buses.size(); ++i) EXPECT_EQ(an386->buses[i].name, an500->buses[i].name);
  EXPECT_TRUE(an500->pwm.empty());
  EXPECT_TRUE(an500->rig_board);
  EXPECT_FALSE(find_board("stm32f4")->pwm.empty());
}

TEST(BoardTable, AnUnknownBoardIsRefusedWithEveryBoardAndItsCore) {
  const std::string why = board_refusal("mps2-an999", image_board_names(), "build images");
  EXPECT_EQ(why,
            "no such board; the boards: mps2-an386 (Cortex-M4F, QEMU's MPS2 AN386), stm32f4 (Cortex-M4F, a "
            "Nucleo-64; in QEMU, the STM32F405 of netduinoplus2), mps2-an500 (Cortex-M7, QEMU's MPS2 AN500), mps2-an385 "
            "(Cortex-M3, QEMU's MPS2 AN385, in a small part's 64 kB of flash and 20 kB of RAM)");
  try {
    board_for("nucleo", "--board");
    FAIL() << "board_for took 'nucleo'";
  } catch (const CliError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--board nucleo: no such board; the boards: mps2-an386 (", 0), 0u)
        << e.what();
    EXPECT_EQ(e.exit_code, 2);
  }
  EXPECT_EQ(board_for("mps2-an500", "--board").image_prefix, "nlsoft-m7");
}

TEST(BoardTable, ABoardThatCannotDoItIsRefusedWithTheBoardsThatCan) {
  EXPECT_EQ(board_refusal("stm32f4", flash_board_names(), "be flashed"), "");
  EXPECT_EQ(board_refusal("mps2-an500", flash_board_names(), "be flashed"),
            "board mps2-an500 cannot be flashed; the boards that can: stm32f4 (Cortex-M4F, a Nucleo-64; in QEMU, "
            "the STM32F405 of netduinoplus2)");
  EXPECT_EQ(board_refusal("mps2-an386", {}, "fly"), "board mps2-an386 cannot fly; the boards that can: none");
}

// The firmware build's boards and image folders (firmware/CMakeLists.txt,
// NLSOFT_IMAGE_BOARDS and NLSOFT_IMAGE_BOARD_DIRS, passed in by CMake).
TEST(BoardTable, IsTheFirmwareBuildsListOfBoards) {
  const Words cmake_boards = split(NLSOFT_CMAKE_IMAGE_BOARDS, ',');
  const Words cmake_dirs = split(NLSOFT_CMAKE_IMAGE_BOARD_DIRS, ',');
  ASSERT_EQ(cmake_boards.size(), cmake_dirs.size());
  EXPECT_EQ(cmake_boards, shipped_board_names());
  for (size_t i = 0; i < cmake_boards.size(); ++i) {
    const std::string& dir = cmake_dirs[i];
    const Board* b = board_named(cmake_boards[i]);
    ASSERT_NE(b, nullptr) << cmake_boards[i];
    EXPECT_EQ(dir.substr(dir.find_last_of('/') + 1), b->image_folder) << cmake_boards[i];
  }
}

// firmware/tools/nlsoft_qemu.py's BOARDS: per board its port, image folder,
// prefix and QEMU arguments, as the table has them.
TEST(BoardTable, IsTheFirmwareToolsListOfBoards) {
  const std::string py = file_text(NLSOFT_SOURCE_DIR "/firmware/tools/nlsoft_qemu.py");
  ASSERT_FALSE(py.empty());
  size_t entries = 0;
  for (const Board& b : boards()) {
    std::string args;
    for (const std::string& a : qemu_machine_args(b, "")) args += (args.empty() ? "\"" : ", \"") + a + "\"";
    args = args.substr(0, args.rfind(", \"-kernel\""));
    const std::string entry = "\"" + b.name + "\": (\"firmware/ports/" + b.name + "\", \"" + b.image_folder +
                              "\", \"" + b.image_prefix + "\",";
    const size_t at = py.find(entry);
    ASSERT_NE(at, std::string::npos) << "nlsoft_qemu.py has no entry " << entry;
    const size_t end = py.find(")", py.find("]", at));
    const std::string rest =
        std::regex_replace(py.substr(at + entry.size(), end - at - entry.size()), std::regex("\\s+"), " ");
    EXPECT_EQ(rest, " [" + args + "]") << b.name;
    ++entries;
  }
  // No board there that the table lacks.
  size_t ports = 0;
  for (size_t at = py.find("\"firmware/ports/"); at != std::string::npos; at = py.find("\"firmware/ports/", at + 1))
    ++ports;
  EXPECT_EQ(ports, entries);
}

// The bash completion's --board words (app/dist/nlsoft-console.bash-completion).
TEST(BoardTable, IsTheBashCompletionsListOfBoards) {
  const std::string text = file_text(NLSOFT_SOURCE_DIR "/app/dist/nlsoft-console.bash-completion");
  const std::string key = "local boards=\"";
  const size_t at = text.find(key);
  ASSERT_NE(at, std::string::npos);
  const size_t from = at + key.size();
  const Words words = split(text.substr(from, text.find('"', from) - from), ' ');
  const Words names = image_board_names();
  EXPECT_EQ(std::set<std::string>(words.begin(), words.end()), std::set<std::string>(names.begin(), names.end()));
}

}  // namespace
}  // namespace nlsoft::host
