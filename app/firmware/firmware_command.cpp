#include "app/firmware/firmware_command.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>

#include "app/firmware/image_build.hpp"
#include "app/firmware/image_header.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/board_option.hpp"
#include "host/rig/rig_option.hpp"

namespace nlsoft::console {

using host::Board;
using host::Rig;
using host::add_rig_option;
using host::board_validator;
using host::boards;
using host::describe_boards;
using host::image_board_names;
using host::load_rig_arg;
using host::rig_arg_help;
using host::rig_arg_validator;

namespace {

void print_image(const char* what, const BuiltImage& b) {
  if (b.path.empty()) return;
  fmt::print("{:<6} {}\n       flash {} bytes, RAM {} bytes\n", what, b.path, b.flash, b.ram);
  // stm32f4: the raw flash contents beside it, what st-flash writes.
  const std::string bin = std::filesystem::path(b.path).replace_extension(".bin").string();
  if (std::filesystem::exists(bin)) fmt::print("       {}\n", bin);
}

}  // namespace

void add_firmware_command(CLI::App& app) {
  CLI::App* fw = app.add_subcommand("firmware", "Cortex-M images for a rig, built from its rig file");
  fw->require_subcommand(1);
  auto q = std::make_shared<ImageBuild>();
  auto rig_arg = std::make_shared<std::string>();
  CLI::App* build = fw->add_subcommand(
      "build", "Generate the rig's image header and build its images with arm-none-eabi-g++ (docs/rig-file.md)");
  add_rig_option(build, *rig_arg, "the rig: a rig file, or a shipped rig's name: " + rig_arg_help())
      ->required()
      ->check(rig_arg_validator());
  build->add_option("--board", q->board, "the board: " + describe_boards(image_board_names()))
      ->required()
      ->check(board_validator(image_board_names(), "build images"));
  build->add_option("--model", q->model,
                    "model file to embed; its layer table is the compiled shape (default: the rig's [model] file "
                    "among the shipped models)")
      ->check(CLI::ExistingFile);
  build->add_option("--out", q->out,
                    "folder for the images (default: the cache folder --qemu, conformance --qemu and flash --rig "
                    "look in, ~/.cache/nlsoft/firmware/<rig>-<board>-<key>)");
  build->add_flag("--hil", q->hil_only, "only the image with the simulated plant in the loop (needs [plant])");
  std::string prefixes;
  for (const Board& b : boards()) prefixes += (prefixes.empty() ? "" : ", ") + b.image_prefix + " (" + b.name + ")";
  build->footer(
      "Builds <prefix>-<rig>.elf, the board's image (stm32f4: PWM and ADC pins from the rig file, and a .bin for\n"
      "st-flash), and, when the rig has a [plant], <prefix>-<rig>-hil.elf with the plant simulated on the MCU;\n"
      "prefix " + prefixes + ".\n"
      "Needs: apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi cmake\n"
      "Examples:\n"
      "  nlsoft-console firmware build --rig lab/arm.toml --board stm32f4\n"
      "  nlsoft-console firmware build --rig lab/arm.toml --board mps2-an386 --out arm-images\n");
  build->callback([q, rig_arg] {
    const BuiltImages b = build_images(load_rig_arg(*rig_arg), *q);
    print_image("board", b.board);
    print_image("hil", b.hil);
  });

  struct HeaderArgs {
    std::string rig, model, out;
  };
  auto h = std::make_shared<HeaderArgs>();
  CLI::App* header = fw->add_subcommand(
      "header", "Write the rig's nlsoft_rig.hpp alone, for a port another tool builds (the Teensy sketch)");
  add_rig_option(header, h->rig, "the rig: a rig file, or a shipped rig's name: " + rig_arg_help())
      ->required()
      ->check(rig_arg_validator());
  header->add_option("--model", h->model, "model file whose layer table is the compiled shape (default: the rig's [model] layers)")
      ->check(CLI::ExistingFile);
  header->add_option("--out", h->out, "folder to write nlsoft_rig.hpp into (created)")->required();
  header->footer(
      "The header every image is compiled from (kRig: the rig's values; Cap: the capacity sized from its\n"
      "dimensions, horizons and one network shape), without a board's pins.\n"
      "Example:\n"
      "  nlsoft-console firmware header --rig msd --out firmware/ports/teensy/nlsoft\n");
  header->callback([h] {
    const Rig rig = load_rig_arg(h->rig);
    ImageRequest request;
    request.board = kPortableBoard;
    request.model_file = h->model;
    const ImageSource source = image_source(rig, request);
    std::filesystem::create_directories(h->out);
    const std::string path = h->out + "/nlsoft_rig.hpp";
    write_text_if_changed(path, source.header);
    fmt::print("wrote {} (rig {}, CRC-32 0x{:08x})\n", path, rig.name, rig.hash);
  });
}

}  // namespace nlsoft::console
