// What the console sends the firmware besides parameters: a reference
// (its kind and values, or a table uploaded), and a new model checked as
// the firmware will check it before a byte goes.
#include "app/live/live_console.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "app/link/model_shape_words.hpp"
#include "app/live/reference_spec.hpp"
#include "app/live/reference_table.hpp"
#include "app/model/model_section.hpp"
#include "shared/capacity.hpp"
#include "shared/model_file.hpp"
#include "app/link/session_words.hpp"

namespace nlsoft::console {

namespace p = nlsoft::protocol;

void LiveConsole::select_reference(const RefParams& ref) {
  device_->select_reference(ref);
  {
    std::lock_guard<std::mutex> lock(mu_);
    reference_ = ref;
    reference_table_file_.clear();
  }
  log_reference_change(reference_json(ref));
}

// A reference sent during a run is part of what the run measured: it goes
// into the run's parameter log with its time, as `reference`.
void LiveConsole::log_reference_change(const std::string& json) {
  if (const int64_t run = run_id_.load()) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_started()).count();
    recorder_->add_param_change(run, t, "reference", json);
  }
}

void LiveConsole::upload_table(const std::string& csv_path, uint16_t hold, const Progress& progress) {
  if (!device_->has(p::capability::kXferRefTable))
    throw CliError("this firmware does not accept reference tables (no XFER_REF_TABLE capability)");
  const ReferenceTablePoints pts = read_reference_csv(csv_path, n());
  device_->upload(p::XferKind::RefTable, reference_table_object(pts), progress);
  RefParams r{};
  r.kind = RefKind::Table;
  r.hold = hold == 0 ? 1 : hold;
  device_->select_reference(r);
  {
    std::lock_guard<std::mutex> lock(mu_);
    reference_ = r;
    reference_table_file_ = csv_path;
  }
  log_reference_change(reference_json(r, csv_path));
}

LiveConsole::ModelUpload LiveConsole::upload_model(const std::string& path, const Progress& progress) {
  if (!device_->has(p::capability::kXferModel))
    throw CliError("this firmware does not accept models (no XFER_MODEL capability)");
  if (running()) throw CliError("a model cannot change during a run: stop the run first");
  // Bounded before a byte is read: by the firmware's model_max, or what the
  // console's own capacity holds if that is more, so that a model of
  // another shape is refused by its shape (RIG_INFO, below) rather than its
  // size; the firmware's limit is checked after that.
  const uint32_t fw_limit = device_->transfer_limit(p::XferKind::Model);
  const uint64_t host_max = model_file_max<HostCapacity>();
  // The model's limit, and room for the sections after it (never sent).
  InputKind kind{"model file", std::max<uint64_t>(fw_limit, host_max) + pipeline::kSectionsMax, false};
  if (fw_limit >= host_max) kind.limit_words = "this firmware takes models of at most";
  const std::string text = read_input_file(path, kind);
  // A file may carry sections after its model (train's fit) the firmware
  // never gets: only the model is checked and sent.
  const pipeline::ModelFileParts parts =
      pipeline::split_model_file(reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (parts.bad_trailer)
    throw CliError(fmt::format("{}: not a usable model file: {}", path, parts.fault));
  const std::vector<uint8_t> bytes(text.begin(), text.begin() + std::ptrdiff_t(parts.model_size));
  // RIG_INFO (protocol 1.2): a shape the firmware has no kernel for would be
  // refused at its header chunk or its commit; refused here, nothing is sent.
  if (const auto rig = device_->rig())
    if (const auto refusal = shape_refusal(path, bytes, *rig)) throw CliError(*refusal);
  // Parsed with copies of the weights, so the check does not depend on the
  // vector's alignment; the same checks the firmware makes at commit.
  std::vector<float> weights(model_params_max<HostCapacity>());
  Model<HostCapacity> m;
  uint8_t file_platform = 255;
  const Status st = parse_model(bytes.data(), bytes.size(), m, weights.data(), uint32_t(weights.size()), &file_platform);
  if (st != Status::Ok) throw CliError(fmt::format("{}: not a usable model file: {}", path, status_name(st)));
  const p::Info info = device_->info();
  if (m.m != info.m || m.n != info.n || m.w != info.w)
    throw CliError(fmt::format("{}: the model has m={} n={} w={}, the firmware's plant m={} n={} w={}", path, m.m, m.n,
                               m.w, info.m, info.n, info.w));
  if (file_platform != 255 && file_platform != info.platform)
    throw CliError(fmt::format("{}: a model of rig {}; the firmware runs {}", path, platform_words(file_platform),
                               platform_words(info.platform)));
  const uint32_t limit = device_->transfer_limit(p::XferKind::Model);
  if (limit != 0 && bytes.size() > limit)
    throw CliError(fmt::format("{}: {} bytes; this firmware takes models of at most {} bytes", path, bytes.size(), limit));

  ModelUpload r;
  r.previous_hash = info.model_hash;
  r.bytes = bytes.size();
  r.params = m.param_count;
  r.normalisation = m.norm_count();
  device_->upload(p::XferKind::Model, bytes, progress);
  r.hash = device_->handshake().model_hash;
  if (r.hash != m.hash)
    throw CliError(fmt::format("the firmware accepted the model but reports hash {:08x}, the file's is {:08x}", r.hash,
                               m.hash));
  return r;
}

std::optional<RefParams> LiveConsole::reference() const {
  std::lock_guard<std::mutex> lock(mu_);
  return reference_;
}

// What a run follows when this console sent no reference: the firmware's
// own choice, named as such. At boot that is the rig's paper task with its
// preset parameters; another kind was selected by someone else, with
// parameters this console cannot read back.
std::string LiveConsole::firmware_reference_json() {
  const Rig* r = nullptr;
  try {
    r = &rig();
  } catch (const std::exception&) {
    return "";
  }
  const uint8_t id = device_->status().ref_id;
  if (id == uint8_t(r->reference.kind)) {
    std::string j = reference_json(rig_reference(*r, r->reference.kind));
    j.pop_back();
    return j + ",\"source\":\"the firmware's start-up reference (the rig file's [reference])\"}";
  }
  if (id >= kRefKindCount) return "";
  return fmt::format("{{\"kind\":\"{}\",\"source\":\"selected before this console connected; parameters not known\"}}",
                     reference_kind_name(RefKind(id)));
}

}  // namespace nlsoft::console
