// A selection is logged into the run in progress; a run that starts
// names what it follows, even when this console selected nothing.
#include "app/live/live_references.hpp"

#include <fmt/format.h>

#include "app/live/reference_spec.hpp"
#include "app/live/reference_table.hpp"
#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::reference_kind_name;
using host::rig_reference;

namespace p = nlsoft::protocol;

void LiveReferences::select(const RefParams& ref) {
  device_.select_reference(ref);
  remember(ref, "");
}

void LiveReferences::remember(const RefParams& ref, const std::string& table_file) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    reference_ = ref;
    table_file_ = table_file;
  }
  run_.log_change("reference", reference_json(ref, table_file));
}

void LiveReferences::upload_table(const std::string& csv_path, uint16_t hold, const Progress& progress) {
  if (const std::string why = device_.lacks(feature::kTableUpload); !why.empty()) throw CliError(why);
  const ReferenceTablePoints pts = read_reference_csv(csv_path, device_.info().n);
  device_.upload(p::XferKind::RefTable, reference_table_object(pts), progress);
  RefParams r{};
  r.kind = RefKind::Table;
  r.hold = hold == 0 ? 1 : hold;
  device_.select_reference(r);
  remember(r, csv_path);
}

std::optional<RefParams> LiveReferences::current() const {
  std::lock_guard<std::mutex> lock(mu_);
  return reference_;
}

std::string LiveReferences::run_json() {
  std::string j;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (reference_) j = reference_json(*reference_, table_file_);
  }
  return j.empty() ? firmware_reference_json() : j;
}

// What a run follows when this console sent no reference: the firmware's
// own choice, named as such. At boot that is the rig's paper task with its
// preset parameters; another kind was selected by someone else, with
// parameters this console cannot read back.
std::string LiveReferences::firmware_reference_json() {
  const Rig* r = nullptr;
  try {
    r = &rig_.rig();
  } catch (const std::exception&) {
    return "";
  }
  const uint8_t id = device_.status().ref_id;
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
