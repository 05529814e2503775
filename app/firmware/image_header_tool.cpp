// nlsoft-image-header: the host build's generator of the shipped images'
// rig headers (firmware/CMakeLists.txt), the same code `nlsoft-console
// firmware build` runs, without the console's other dependencies in the way
// of the first image build.
//
//   nlsoft-image-header --rig rigs/tendon.toml --board stm32f4 --out DIR [--model F | --no-model]
//                       [--shape dense:10,dense:5,dense:3] [--images both|board|hil|runnable]
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "app/firmware/image_header.hpp"
#include "host/rig/board_table.hpp"

int main(int argc, char** argv) {
  using namespace nlsoft::console;
  using nlsoft::host::CliError;
  using nlsoft::host::Rig;
  using nlsoft::host::RigError;
  using nlsoft::host::RigLayer;
  using nlsoft::host::describe_boards;
  using nlsoft::host::image_board_names;
  using nlsoft::host::load_rig;
  CLI::App app{"Writes an image's nlsoft_rig.hpp and image.cmake from a rig file"};
  std::string rig_file, board, out, model, shape, images = "both";
  bool no_model = false;
  app.add_option("--rig", rig_file, "the rig file")->required();
  app.add_option("--board", board, "the board: " + describe_boards(image_board_names()))->required();
  app.add_option("--out", out, "the folder to write into")->required();
  app.add_option("--model", model, "the model file the image embeds; its layer table is the shape");
  app.add_flag("--no-model", no_model, "embed no model (the shape from --shape or the rig's [model] layers)");
  app.add_option("--shape", shape, "layers as kind:units,... (dense or gru), instead of the rig's");
  app.add_option("--images", images,
                 "which images the header is for: both, board, hil, or runnable (what the board can run: both on "
                 "the rig's board or for a rig without chips, the HIL image alone on another board)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    const Rig rig = load_rig(rig_file);
    ImageRequest request;
    request.board = board;
    request.images = parse_image_kinds(images, "--images");
    // The model part alone, beside the header (a trained file carries its fit after it).
    if (!no_model && !model.empty()) request.model_file = model_copy_for_image(model, out);
    std::stringstream layers(shape);
    for (std::string item; std::getline(layers, item, ',');) {
      const size_t colon = item.find(':');
      if (colon == std::string::npos) throw CliError("--shape " + shape + ": kind:units, e.g. dense:10");
      const nlsoft::LayerKindInfo* kind = nlsoft::layer_kind_named(item.substr(0, colon).c_str());
      RigLayer l;
      l.units = std::stoi(item.substr(colon + 1));
      if (kind == nullptr || l.units <= 0) throw CliError("--shape " + shape + ": kind dense or gru, units > 0");
      l.kind = kind->kind;
      request.layers.push_back(l);
    }
    const ImageSource source = image_source(rig, request);
    // Into the build log: a board that gets fewer images than the others is said.
    if (!source.board && !source.note.empty()) std::printf("nlsoft-image-header: %s\n", source.note.c_str());
    write_image_source(source, out);
  } catch (const RigError& e) {
    std::fprintf(stderr, "nlsoft-image-header: %s\n", e.what());
    return 2;
  } catch (const CliError& e) {
    std::fprintf(stderr, "nlsoft-image-header: %s\n", e.what());
    return e.exit_code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nlsoft-image-header: %s\n", e.what());
    return 2;
  }
  return 0;
}
