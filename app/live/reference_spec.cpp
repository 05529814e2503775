#include "app/live/reference_spec.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "host/files/cli_error.hpp"
#include "app/reference_names.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::reference_kind_name;

namespace {

constexpr double kTwoPi = 6.283185307179586;

float number(const std::string& key, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0')
    throw CliError(fmt::format("{}={}: '{}' is not a number", key, text, text));
  if (!std::isfinite(v)) throw CliError(fmt::format("{}={}: must be finite", key, text));
  return float(v);
}

}  // namespace

std::vector<std::string> reference_spec_names() {
  std::vector<std::string> names = reference_names();
  names.push_back("step");
  return names;
}

const std::vector<std::string>& reference_keys() {
  static const std::vector<std::string> keys = {"a",     "b",      "c",      "c0",    "c1",   "c2",
                                                "omega", "lambda", "period", "scale", "hold", "levels"};
  return keys;
}

std::vector<std::string> reference_keys_for(RefKind kind) {
  switch (kind) {
    case RefKind::Infinity: return {"a", "b", "c", "c0", "c1", "c2", "period", "omega"};
    case RefKind::Pringle:
    case RefKind::Diagonal: return {"a", "b", "c", "c0", "c1", "c2", "period", "lambda"};
    case RefKind::Swirl: return {"scale", "hold", "c0", "c1", "c2"};
    case RefKind::Step: return {"levels", "hold", "c0", "c1", "c2"};
    case RefKind::Table: return {"hold"};
    case RefKind::Hold: return {"c0", "c1", "c2"};
  }
  return {};
}

void set_reference_key(RefParams& r, double rate, const std::string& key, const std::string& value) {
  if (key == "a") r.A = number(key, value);
  else if (key == "b") r.B = number(key, value);
  else if (key == "c") r.C = number(key, value);
  else if (key == "c0") r.c[0] = number(key, value);
  else if (key == "c1") r.c[1] = number(key, value);
  else if (key == "c2") r.c[2] = number(key, value);
  else if (key == "omega") r.omega = number(key, value);
  else if (key == "lambda") r.lambda = number(key, value);
  else if (key == "scale") r.scale = number(key, value);
  else if (key == "period") {
    // One lap in seconds: the natural unit for a person; the firmware wants
    // rad per step (Infinity) or steps per lap (Pringle, Diagonal).
    const float s = number(key, value);
    if (!(s > 0)) throw CliError(fmt::format("period={}: must be > 0 seconds", value));
    r.lambda = float(double(s) * rate);
    r.omega = float(kTwoPi / (double(s) * rate));
  } else if (key == "hold") {
    const float h = number(key, value);
    if (h < 1 || h > 65535 || h != std::floor(h))
      throw CliError(fmt::format("hold={}: must be a whole number of control steps, 1..65535", value));
    r.hold = uint16_t(h);
  } else if (key == "levels") {
    int count = 0;
    size_t pos = 0;
    while (pos <= value.size()) {
      const size_t comma = value.find(',', pos);
      const std::string item = value.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
      if (count == kRefMaxLevels) throw CliError(fmt::format("levels={}: at most {} levels", value, kRefMaxLevels));
      r.levels[count++] = number("levels", item);
      if (comma == std::string::npos) break;
      pos = comma + 1;
    }
    r.level_count = uint8_t(count);
  } else {
    std::string known;
    for (const auto& k : reference_keys()) known += (known.empty() ? "" : " ") + k;
    throw CliError(fmt::format("unknown reference key '{}'; known: {}", key, known));
  }
}

std::string reference_key_value(const RefParams& r, double rate, const std::string& key) {
  if (key == "a") return fmt::format("{:g}", r.A);
  if (key == "b") return fmt::format("{:g}", r.B);
  if (key == "c") return fmt::format("{:g}", r.C);
  if (key == "c0") return fmt::format("{:g}", r.c[0]);
  if (key == "c1") return fmt::format("{:g}", r.c[1]);
  if (key == "c2") return fmt::format("{:g}", r.c[2]);
  if (key == "omega") return fmt::format("{:g}", r.omega);
  if (key == "lambda") return fmt::format("{:g}", r.lambda);
  if (key == "scale") return fmt::format("{:g}", r.scale);
  if (key == "hold") return fmt::format("{}", r.hold);
  if (key == "period") {
    if (r.kind == RefKind::Infinity) return r.omega > 0 ? fmt::format("{:g}", kTwoPi / double(r.omega) / rate) : "";
    return rate > 0 ? fmt::format("{:g}", double(r.lambda) / rate) : "";
  }
  if (key == "levels") {
    std::string s;
    for (int i = 0; i < r.level_count && i < kRefMaxLevels; ++i) s += (i ? "," : "") + fmt::format("{:g}", r.levels[i]);
    return s;
  }
  return "";
}

RefParams reference_from_spec(const Rig& rig, double rate, const std::string& name,
                              const std::vector<std::pair<std::string, std::string>>& options) {
  RefParams r = reference_by_name(rig, name == "step" ? "steps" : name);
  for (const auto& [k, v] : options) set_reference_key(r, rate, k, v);
  if (const char* why = reference_check(r)) throw CliError(fmt::format("ref {}: {}", name, why));
  return r;
}

std::string reference_json(const RefParams& r, const std::string& table_file) {
  nlohmann::json j;
  j["kind"] = reference_kind_name(r.kind);
  j["hold"] = r.hold;
  j["a"] = r.A, j["b"] = r.B, j["c"] = r.C;
  j["center"] = {r.c[0], r.c[1], r.c[2]};
  j["omega"] = r.omega, j["lambda"] = r.lambda, j["scale"] = r.scale;
  j["levels"] = std::vector<float>(r.levels, r.levels + std::min<int>(r.level_count, kRefMaxLevels));
  if (!table_file.empty()) j["table"] = table_file;
  return j.dump();
}

RefParams reference_from_json(const std::string& text, const std::string& where) {
  RefParams r{};
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    const std::string kind = j.at("kind").get<std::string>();
    bool known = false;
    for (int k = 0; k < kRefKindCount; ++k)
      if (kind == reference_kind_name(RefKind(k))) r.kind = RefKind(k), known = true;
    if (!known) throw CliError(fmt::format("{}: reference kind '{}' is not one this console knows", where, kind));
    if (r.kind == RefKind::Table)
      throw CliError(fmt::format("{}: the reference was an uploaded table{}, whose points a run does not keep", where,
                                 j.contains("table") ? " (" + j.at("table").get<std::string>() + ")" : ""));
    r.hold = j.at("hold").get<uint16_t>();
    r.A = j.at("a").get<float>(), r.B = j.at("b").get<float>(), r.C = j.at("c").get<float>();
    const auto& c = j.at("center");
    for (int i = 0; i < 3; ++i) r.c[i] = c.at(size_t(i)).get<float>();
    r.omega = j.at("omega").get<float>(), r.lambda = j.at("lambda").get<float>(), r.scale = j.at("scale").get<float>();
    const auto& levels = j.at("levels");
    if (levels.size() > size_t(kRefMaxLevels))
      throw CliError(fmt::format("{}: {} step levels, at most {}", where, levels.size(), kRefMaxLevels));
    r.level_count = uint8_t(levels.size());
    for (size_t i = 0; i < levels.size(); ++i) r.levels[i] = levels[i].get<float>();
  } catch (const nlohmann::json::exception& e) {
    throw CliError(fmt::format("{}: not a reference as the console records one: {}", where, e.what()));
  }
  if (const char* why = reference_check(r)) throw CliError(fmt::format("{}: the reference is refused: {}", where, why));
  return r;
}

}  // namespace nlsoft::console
