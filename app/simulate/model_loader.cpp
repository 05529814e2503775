#include "app/simulate/model_loader.hpp"

#include <fmt/format.h>


#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "app/model/model_section.hpp"
#include "host/paths/install_paths.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::console {

using host::CliError;
using host::read_input_file;

void load_model(const std::string& path, LoadedModel& out) {
  std::string text;
  try {
    text = read_input_file(path, {"model file", model::model_file_with_sections_max(), false});
  } catch (const CliError& e) {
    throw CliError(fmt::format("cannot open model file '{}': {}", path, e.what()));
  }
  // The model alone: sections after it (train's fit) are not the controller's.
  const model::ModelFileParts parts =
      model::split_model_file(reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (parts.bad_trailer) throw CliError(fmt::format("model file '{}' refused: {}", path, parts.fault));
  std::vector<uint8_t> bytes(text.begin(), text.begin() + std::ptrdiff_t(parts.model_size));
  std::vector<float> storage(HostCapacity::weights + 2 * Dims<HostCapacity>::p + 2 * HostCapacity::n);
  Model<HostCapacity> M;
  uint8_t platform = 255;
  const Status s = parse_model(bytes.data(), bytes.size(), M, storage.data(), uint32_t(storage.size()), &platform);
  if (s != Status::Ok)
    throw CliError(fmt::format("model file '{}' refused: {} (an nlsoft model file, written by `nlsoft-console "
                               "train` or `model import`, is expected)",
                               path, status_name(s)));
  out.storage = std::move(storage);
  M.params = out.storage.data();
  out.model = M;
  out.file = std::move(bytes);
  out.path = path;
  out.platform = platform;
}

}  // namespace nlsoft::console
