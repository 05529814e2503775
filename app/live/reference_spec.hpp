#pragma once
// `ref NAME key=value...`: a named path sized for the rig's task space
// (its rig file's [reference] and output spans, app/reference_names) with any of its parameters overridden, and the
// reverse, a RefParams as JSON for the runs table.
#include <string>
#include <utility>
#include <vector>

#include "host/rig/rig_reference.hpp"  // reference_kind_name
#include "host/rig/rig.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

// Names the `ref` command accepts (presets plus "step" for "steps").
std::vector<std::string> reference_spec_names();
// Keys a reference takes: a b c c0 c1 c2 omega lambda period scale hold levels.
const std::vector<std::string>& reference_keys();

// Throws CliError for an unknown name or key, a malformed number or a set
// the firmware would refuse anyway (shared/reference.hpp's reference_check).
RefParams reference_from_spec(const host::Rig& rig, double loop_rate_hz, const std::string& name,
                              const std::vector<std::pair<std::string, std::string>>& options);

// Applies one key=value to r (used by the spec and the TUI editor).
void set_reference_key(RefParams& r, double loop_rate_hz, const std::string& key, const std::string& value);
// Current value of a key as text ("" for keys the kind does not use).
std::string reference_key_value(const RefParams& r, double loop_rate_hz, const std::string& key);
// Keys that matter for r.kind, in display order.
std::vector<std::string> reference_keys_for(RefKind kind);

std::string reference_json(const RefParams& r, const std::string& table_file = {});

// The reverse, for a run's reference as the runs table keeps it: the same
// floats back (each was written exactly). Throws CliError naming `where`
// for a text that is not one, a kind without its parameters in the text
// (an uploaded table: its points are not kept) or values the firmware
// would refuse.
RefParams reference_from_json(const std::string& text, const std::string& where);

}  // namespace nlsoft::console
