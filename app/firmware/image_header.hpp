#pragma once
// The header a Cortex-M image is compiled for (firmware/ports/cortex-m/
// platform_config.hpp includes it as "nlsoft_rig.hpp"): the rig as a
// constexpr RigConfig, the capacity sized from the rig's dimensions and
// horizons with the model's shape as the one compiled kernel, the simulated
// plant of the HIL image, and on stm32f4 the rig's pins. Beside it, the
// image.cmake the port project reads (the image's name, the model it
// embeds, whether a HIL image exists). The shipped images and
// `nlsoft-console firmware build` are made from the same text.
#include <string>
#include <vector>

#include "host/rig/rig.hpp"

namespace nlsoft::console {

// The board of a header with no board's pins: for a port another tool
// builds (the Teensy sketch, `firmware header`).
inline const char* const kPortableBoard = "portable";

// Which images a header is for. A board image reads the rig's chips over
// the board's buses, so it is built only for the rig file's board (or for
// any board when the rig names no chip); a HIL image reads no chip (the
// simulated plant gives every sensor channel), so any board runs it.
// Runnable asks for what the board can run: both images on the rig's own
// board or for a chipless rig, the HIL image alone on another board (the
// shipped build, which makes every rig's images for every board).
enum class ImageKinds { Both, Board, Hil, Runnable };
// "both", "board", "hil", "runnable"; parse_image_kinds throws CliError
// naming `option` for another word.
const char* image_kinds_name(ImageKinds k);
ImageKinds parse_image_kinds(const std::string& word, const std::string& option);

struct ImageRequest {
  std::string board;                // a board of the board table (host/rig/board_table.hpp), or kPortableBoard
  ImageKinds images = ImageKinds::Both;
  std::string model_file;           // embedded and its layer table is the shape; empty: none embedded
  std::vector<host::RigLayer> layers;  // with no model_file: the shape (default: the rig's [model] layers)
};

struct ImageSource {
  std::string header;  // nlsoft_rig.hpp
  std::string cmake;   // image.cmake
  bool board = false;  // the header is for the board image (image.cmake's NLSOFT_IMAGE_BOARD)
  bool hil = false;    // ... and for the HIL image: asked for, and the rig has a plant
  std::string note;    // what the image leaves out of the file that the user should hear (one sentence), or empty
};

// Throws RigError ("file:line: ...") for what the board cannot take (a
// board image of chips on another board's buses, a HIL image of a rig
// without a plant), and CliError for a model that does not fit the rig.
ImageSource image_source(const host::Rig& rig, const ImageRequest& request);

// The parts, each a piece of the header. The plant part is the one place
// that knows which simulated plants an image can carry: empty when the rig
// has none (only the real-board image is built then).
std::string rig_config_part(const host::Rig& rig);
std::string capacity_part(const host::Rig& rig, const std::vector<host::RigLayer>& layers);
std::string plant_part(const host::Rig& rig);
std::string pins_part(const host::Rig& rig, const std::string& board);
// The sensor chips and each sensor channel's source (image_devices.cpp).
std::string devices_part(const host::Rig& rig);

// The layer table of a model file, as [[model.layer]] would spell it;
// throws CliError when the file cannot be read or does not fit the rig.
std::vector<host::RigLayer> model_layers(const std::string& model_file, const host::Rig& rig);

// Writes nlsoft_rig.hpp and image.cmake into `dir` (created), replacing
// files only whose text changed so an unchanged rig rebuilds nothing.
void write_image_source(const ImageSource& source, const std::string& dir);

// The model part of `model_file` (what a file carries after it, train's fit,
// is not the firmware's, and its boot parse would refuse it) copied to
// `dir`/model.nlsm, rewritten only when it changes; returns that path. Every
// image embeds such a copy, never the file the user named.
std::string model_copy_for_image(const std::string& model_file, const std::string& dir);

// `text` into `path` through a temporary renamed over it, only when the
// file holds other text (its time stamp then stays, and nothing relinks).
void write_text_if_changed(const std::string& path, const std::string& text);

}  // namespace nlsoft::console
