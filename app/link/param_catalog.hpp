#pragma once
// The firmware's parameter list as the console knows it: built from
// PARAM_DESC replies only (never from shared/params.hpp), so a firmware with
// other parameters gets an editor for those.
#include <cstdint>
#include <string>
#include <vector>

#include "protocol/messages.hpp"

namespace nlsoft::console {

struct ParamInfo {
  uint16_t index = 0, id = 0;
  protocol::ParamType type = protocol::ParamType::F32;
  uint8_t size = 1;
  uint8_t access = 0;
  float min = 0, max = 0;
  std::string unit, name;
  // Set when this build holds less than the table's range (the horizons:
  // INFO's max_n, max_nc): max is then that capacity, and this names it.
  std::string capacity;

  bool read_only() const { return access & protocol::param_access::kReadOnly; }
  bool stopped_only() const { return access & protocol::param_access::kStoppedOnly; }
  bool is_float() const { return type == protocol::ParamType::F32; }
};

ParamInfo param_info_from(const protocol::ParamDesc& d);

// The horizons' real range: PARAM_DESC gives the table's bound (255 steps
// for every build), INFO the build's capacity; N and N1 go up to max_n, Nc
// to max_nc, and the console advertises and checks that.
void apply_capacity(std::vector<ParamInfo>& params, unsigned max_n, unsigned max_nc);

class ParamCatalog {
 public:
  ParamCatalog() = default;
  explicit ParamCatalog(std::vector<ParamInfo> params) : params_(std::move(params)) {}

  const std::vector<ParamInfo>& all() const { return params_; }
  bool empty() const { return params_.empty(); }
  // Exact name first, then case-insensitive; nullptr if neither.
  const ParamInfo* find(const std::string& name) const;
  const ParamInfo* find_id(uint16_t id) const;
  // Throws CliError naming the known parameters.
  const ParamInfo& require(const std::string& name) const;
  std::string names() const;

 private:
  std::vector<ParamInfo> params_;
};

// Text -> values for one parameter: every token a number, the right count,
// whole numbers for integer types. Throws CliError in words; range checks are
// the firmware's (its NACK is the authority, and it knows cross-rules).
std::vector<double> parse_param_values(const ParamInfo& p, const std::vector<std::string>& tokens);

// Values <-> PARAM_SET/PARAM_VALUE words.
void encode_param_values(const ParamInfo& p, const std::vector<double>& values, uint32_t* words);
std::vector<double> decode_param_values(const ParamInfo& p, const uint32_t* words, uint8_t count);

// "1e+06 2e+06 1e+06" (space separated, round-trips through parse).
std::string format_param_values(const ParamInfo& p, const std::vector<double>& values);

// A NACK of PARAM_SET in the parameter's own words:
// "Q[1] = -2 is out of range [0, 1e+12]".
std::string describe_param_refusal(const ParamInfo& p, const protocol::Nack& nack, const std::vector<double>& sent);

}  // namespace nlsoft::console
