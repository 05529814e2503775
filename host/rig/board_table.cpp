#include "host/rig/board_table.hpp"

#include "host/files/cli_error.hpp"

namespace nlsoft::host {

const std::vector<Board>& boards() {
  static const std::vector<Board> all = {
      {"mps2-an386", "Cortex-M4F", "QEMU's MPS2 AN386", "m4", "nlsoft-m4", "mps2-an386",
       // UART0, the machine's first serial port.
       {"pty"}, "", PinTable::Mps2Shields},
      {"stm32f4", "Cortex-M4F", "a Nucleo-64; in QEMU, the STM32F405 of netduinoplus2", "stm32f4", "nlsoft-stm32f4",
       "netduinoplus2",
       // USART2 is the STM32F405's second serial port; the first (USART1) goes nowhere.
       {"null", "pty"},
       // openocd's own description of every ST Nucleo-64 with an F4: ST-LINK/V2-1
       // over SWD, target stm32f4x; the same file serves the F401, F411 and F446.
       "board/st_nucleo_f4.cfg", PinTable::Stm32f4},
      // The AN386's peripherals at the AN386's addresses around a Cortex-M7
      // (QEMU 7.2, hw/arm/mps2.c): the same shield buses and UART0.
      {"mps2-an500", "Cortex-M7", "QEMU's MPS2 AN500", "m7", "nlsoft-m7", "mps2-an500", {"pty"}, "",
       PinTable::Mps2Shields},
      // A small part: the AN386's peripherals around a Cortex-M3 without an
      // FPU (QEMU, hw/arm/mps2.c), linked into 64 kB of flash and 20 kB of
      // RAM (firmware/ports/mps2-an385/an385.ld); a shipped rig with every
      // service does not fit, its minimum does.
      {"mps2-an385", "Cortex-M3", "QEMU's MPS2 AN385, in a small part's 64 kB of flash and 20 kB of RAM", "m3",
       "nlsoft-m3", "mps2-an385", {"pty"}, "", PinTable::Mps2Shields, false},
  };
  return all;
}

const Board* board_named(const std::string& name) {
  for (const Board& b : boards())
    if (b.name == name) return &b;
  return nullptr;
}

std::string describe_boards(const std::vector<std::string>& names) {
  std::string list;
  for (const std::string& name : names) {
    const Board* b = board_named(name);
    list += (list.empty() ? "" : ", ") + name + (b ? " (" + b->cpu + ", " + b->description + ")" : "");
  }
  return list;
}

std::string board_refusal(const std::string& name, const std::vector<std::string>& allowed, const std::string& doing) {
  if (!board_named(name)) return "no such board; the boards: " + describe_boards(image_board_names());
  for (const std::string& a : allowed)
    if (a == name) return "";
  return "board " + name + " cannot " + doing + "; the boards that can: " +
         (allowed.empty() ? std::string("none") : describe_boards(allowed));
}

const Board& board_for(const std::string& name, const std::string& option) {
  if (const Board* b = board_named(name)) return *b;
  throw CliError(option + " " + name + ": " + board_refusal(name, {}, ""));
}

namespace {

template <class Keep>
std::vector<std::string> names_where(Keep keep) {
  std::vector<std::string> names;
  for (const Board& b : boards())
    if (keep(b)) names.push_back(b.name);
  return names;
}

}  // namespace

std::vector<std::string> image_board_names() {
  return names_where([](const Board&) { return true; });
}

std::vector<std::string> shipped_board_names() {
  return names_where([](const Board& b) { return b.shipped; });
}

std::vector<std::string> qemu_board_names() {
  return names_where([](const Board& b) { return !b.qemu_machine.empty(); });
}

std::vector<std::string> flash_board_names() {
  return names_where([](const Board& b) { return !b.openocd_config.empty(); });
}

std::string image_file_name(const Board& board, const std::string& rig, bool hil) {
  return board.image_prefix + "-" + rig + (hil ? "-hil" : "") + ".elf";
}

std::string shipped_image(const Board& board, const std::string& rig, bool hil) {
  return board.image_folder + "/" + image_file_name(board, rig, hil);
}

std::vector<std::string> qemu_machine_args(const Board& board, const std::string& elf) {
  std::vector<std::string> args = {"-M", board.qemu_machine};
  for (const std::string& s : board.qemu_serial) args.insert(args.end(), {"-serial", s});
  args.insert(args.end(), {"-kernel", elf});
  return args;
}

}  // namespace nlsoft::host
