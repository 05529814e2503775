#pragma once
// The boards the firmware is built for, one descriptor each: everything the
// console knows about a board (its name, core, image folder and names, the
// QEMU machine that boots it, how it is flashed, its pin table) is read from
// here and nowhere else spelt. The firmware build's list of boards
// (firmware/CMakeLists.txt, NLSOFT_IMAGE_BOARDS) names the same boards and
// image folders; tests/host/rig/test_board_table.cpp holds the two equal.
#include <string>
#include <vector>

namespace nlsoft::host {

// Which pins and buses a rig file may name on the board (board_pins.cpp
// builds each from the firmware's own tables).
enum class PinTable {
  Stm32f4,      // PWM outputs, ADC channels, I2C/SPI on pins: shared/board_stm32f4.hpp
  Mps2Shields,  // no pins; the MPS2 FPGA's shield buses (firmware/ports/mps2-an386/buses.hpp)
};

struct Board {
  std::string name;         // --board, a rig file's `board`, and its port: firmware/ports/<name>
  std::string cpu;          // the core the images are compiled for: "Cortex-M4F"
  std::string description;  // what it is, for --help: "QEMU's MPS2 AN386"
  // build/firmware/<image_folder>/ and share/nlsoft/firmware/<image_folder>/
  // hold the shipped images, <image_prefix>-<rig>[-hil].elf.
  std::string image_folder, image_prefix;
  std::string qemu_machine;               // qemu-system-arm -M; its images run under QEMU
  std::vector<std::string> qemu_serial;   // the -serial arguments that put the link's UART on the pty
  std::string openocd_config;             // `flash` writes it with openocd -f this; empty: it cannot
  PinTable pins = PinTable::Mps2Shields;
  // The main build builds its images of the shipped rigs (firmware/CMakeLists.txt,
  // NLSOFT_IMAGE_BOARDS); a small part's are built for a rig file that fits it.
  bool shipped = true;
};

// Every board, in the order --help lists them.
const std::vector<Board>& boards();
// nullptr for a name that is no board's.
const Board* board_named(const std::string& name);
// Why `name` will not do where only the boards `allowed` will ("" when it
// will): "no such board; the boards: mps2-an386 (Cortex-M4F, QEMU's MPS2
// AN386), ..." listing every board and what it is, or "board stm32f4 cannot
// <doing>; the boards that can: ...".
std::string board_refusal(const std::string& name, const std::vector<std::string>& allowed, const std::string& doing);
// The board `name`, or a CliError "<option> <name>: " + board_refusal.
const Board& board_for(const std::string& name, const std::string& option);

// Every board's name (the boards images are built for); those whose images
// QEMU boots; those `flash` writes.
std::vector<std::string> image_board_names();
// The boards the main build makes the shipped rigs' images for.
std::vector<std::string> shipped_board_names();
std::vector<std::string> qemu_board_names();
std::vector<std::string> flash_board_names();
// "mps2-an386 (Cortex-M4F, QEMU's MPS2 AN386), stm32f4 (...)": the boards
// named, each with its core and what it is, for --help and errors.
std::string describe_boards(const std::vector<std::string>& names);
// The board `--qemu` boots when no --board is given.
inline const char* const kDefaultQemuBoard = "mps2-an386";

// "m4/nlsoft-m4-hasel-hil.elf": a shipped image, relative to the image folders.
std::string shipped_image(const Board& board, const std::string& rig, bool hil);
// "nlsoft-m4-hasel-hil.elf": an image's file name.
std::string image_file_name(const Board& board, const std::string& rig, bool hil);
// qemu-system-arm's arguments that boot `elf` on the board with the link on
// a pty (after "qemu-system-arm -nographic -monitor none").
std::vector<std::string> qemu_machine_args(const Board& board, const std::string& elf);

}  // namespace nlsoft::host
