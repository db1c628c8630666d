#include "wire/params_json.h"

#include <google/protobuf/util/json_util.h>

#include <string>

#include "wire/service_error.h"

namespace mesh4d::wire {
namespace {

[[noreturn]] void bad(const std::string& message) {
  throw ServiceError(ErrorCode::invalid_argument, message);
}

}  // namespace

void read_params(const nlohmann::json& object, v1::RefineParams* params) {
  if (!object.is_object())
    bad("params must be a JSON object of RefineParams fields, e.g. {\"delta\": 5}");
  const auto* descriptor = v1::RefineParams::descriptor();
  for (const auto& [key, value] : object.items()) {
    if (descriptor->FindFieldByName(key)) continue;
    std::string known;
    for (int i = 0; i < descriptor->field_count(); ++i)
      known += (i ? ", " : "") + descriptor->field(i)->name();
    bad("unknown parameter '" + key + "' (the parameters are " + known + ")");
  }
  nlohmann::json fields = object;
  // The short names of the rule orders, and the proto's own.
  if (auto it = fields.find("rule_order"); it != fields.end()) {
    const std::string order = it->is_string() ? it->get<std::string>() : it->dump();
    if (order == "paper" || order == "RULE_ORDER_PAPER")
      *it = "RULE_ORDER_PAPER";
    else if (order == "r3_first" || order == "RULE_ORDER_R3_FIRST")
      *it = "RULE_ORDER_R3_FIRST";
    else
      bad("rule_order '" + order + "' is not one of r3_first, paper");
  }
  // The same for time: open or periodic.
  if (auto it = fields.find("time_topology"); it != fields.end()) {
    const std::string topology = it->is_string() ? it->get<std::string>() : it->dump();
    if (topology == "periodic" || topology == "TIME_TOPOLOGY_PERIODIC")
      *it = "TIME_TOPOLOGY_PERIODIC";
    else if (topology == "open" || topology == "TIME_TOPOLOGY_OPEN")
      *it = "TIME_TOPOLOGY_OPEN";
    else
      bad("time_topology '" + topology + "' is not one of open, periodic");
  }
  // Protobuf's JSON parser checks the values' types; parsed into a fresh message so that the
  // fields not named keep their values.
  v1::RefineParams parsed;
  const auto status = google::protobuf::util::JsonStringToMessage(fields.dump(), &parsed);
  if (!status.ok()) bad("bad parameter: " + std::string(status.message()));
  params->MergeFrom(parsed);
}

void parse_params(std::string_view json_text, v1::RefineParams* params) {
  const auto object = nlohmann::json::parse(json_text, nullptr, false);
  if (object.is_discarded()) bad("params are not valid JSON");
  read_params(object, params);
}

}  // namespace mesh4d::wire
