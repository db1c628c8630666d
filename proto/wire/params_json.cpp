#include "wire/params_json.h"

#include <google/protobuf/util/json_util.h>

#include <cctype>
#include <initializer_list>
#include <string>

#include "wire/service_error.h"

namespace mesh4d::wire {
namespace {

[[noreturn]] void bad(const std::string& message) {
  throw ServiceError(ErrorCode::invalid_argument, message);
}

// The enum field `key`, when present, as the proto names its value: a short name (lower case,
// what follows `prefix`) or the proto's own; anything else is refused, naming the short ones.
void spell_enum(nlohmann::json& fields, const char* key, const std::string& prefix,
                std::initializer_list<const char*> names) {
  const auto it = fields.find(key);
  if (it == fields.end()) return;
  const std::string value = it->is_string() ? it->get<std::string>() : it->dump();
  std::string listed;
  for (const std::string name : names) {
    std::string upper = name;
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (value == name || value == prefix + upper) {
      *it = prefix + upper;
      return;
    }
    listed += (listed.empty() ? "" : ", ") + name;
  }
  bad(std::string(key) + " '" + value + "' is not one of " + listed);
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
  // The short names of the enums' values, and the proto's own.
  spell_enum(fields, "rule_order", "RULE_ORDER_", {"r3_first", "paper"});
  spell_enum(fields, "time_topology", "TIME_TOPOLOGY_", {"open", "periodic"});
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
