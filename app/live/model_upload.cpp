// The model file is bounded before it is read, split from the sections
// only the console uses, and checked as the firmware will check it; the
// hash the firmware reports afterwards must be the file's.
#include "app/live/model_upload.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "app/link/model_shape_words.hpp"
#include "app/link/session_words.hpp"
#include "app/model/model_section.hpp"
#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "shared/capacity.hpp"
#include "shared/model_file.hpp"

namespace nlsoft::console {

using host::CliError;
using host::InputKind;
using host::read_input_file;

namespace p = nlsoft::protocol;

ModelUpload::Result ModelUpload::send(const std::string& path, const Progress& progress) {
  if (const std::string why = device_.lacks(feature::kModelUpload); !why.empty()) throw CliError(why);
  if (run_.id.load() != 0) throw CliError("a model cannot change during a run: stop the run first");
  // Bounded before a byte is read: by the firmware's model_max, or what the
  // console's own capacity holds if that is more, so that a model of
  // another shape is refused by its shape (RIG_INFO, below) rather than its
  // size; the firmware's limit is checked after that.
  const uint32_t fw_limit = device_.transfer_limit(p::XferKind::Model);
  const uint64_t host_max = model_file_max<HostCapacity>();
  // The model's limit, and room for the sections after it (never sent).
  InputKind kind{"model file", std::max<uint64_t>(fw_limit, host_max) + model::kSectionsMax, false};
  if (fw_limit >= host_max) kind.limit_words = "this firmware takes models of at most";
  const std::string text = read_input_file(path, kind);
  // A file may carry sections after its model (train's fit) the firmware
  // never gets: only the model is checked and sent.
  const model::ModelFileParts parts =
      model::split_model_file(reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (parts.bad_trailer)
    throw CliError(fmt::format("{}: not a usable model file: {}", path, parts.fault));
  const std::vector<uint8_t> bytes(text.begin(), text.begin() + std::ptrdiff_t(parts.model_size));
  // RIG_INFO (protocol 1.2): a shape the firmware has no kernel for would be
  // refused at its header chunk or its commit; refused here, nothing is sent.
  if (const auto rig = device_.rig())
    if (const auto refusal = shape_refusal(path, bytes, *rig)) throw CliError(*refusal);
  // Parsed with copies of the weights, so the check does not depend on the
  // vector's alignment; the same checks the firmware makes at commit.
  std::vector<float> weights(model_params_max<HostCapacity>());
  Model<HostCapacity> m;
  uint8_t file_platform = 255;
  const Status st = parse_model(bytes.data(), bytes.size(), m, weights.data(), uint32_t(weights.size()), &file_platform);
  if (st != Status::Ok) throw CliError(fmt::format("{}: not a usable model file: {}", path, status_name(st)));
  const p::Info info = device_.info();
  if (m.m != info.m || m.n != info.n || m.w != info.w)
    throw CliError(fmt::format("{}: the model has m={} n={} w={}, the firmware's plant m={} n={} w={}", path, m.m, m.n,
                               m.w, info.m, info.n, info.w));
  if (file_platform != 255 && file_platform != info.platform)
    throw CliError(fmt::format("{}: a model of rig {}; the firmware runs {}", path, platform_words(file_platform),
                               platform_words(info.platform)));
  const uint32_t limit = device_.transfer_limit(p::XferKind::Model);
  if (limit != 0 && bytes.size() > limit)
    throw CliError(fmt::format("{}: {} bytes; this firmware takes models of at most {} bytes", path, bytes.size(), limit));

  Result r;
  r.previous_hash = info.model_hash;
  r.bytes = bytes.size();
  r.params = m.param_count;
  r.normalisation = m.norm_count();
  device_.upload(p::XferKind::Model, bytes, progress);
  r.hash = device_.handshake().model_hash;
  if (r.hash != m.hash)
    throw CliError(fmt::format("the firmware accepted the model but reports hash {:08x}, the file's is {:08x}", r.hash,
                               m.hash));
  return r;
}

}  // namespace nlsoft::console
