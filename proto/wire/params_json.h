// RefineParams from JSON, one parser for every face: the client's --params file and the REST
// face's query, form part or JSON object. Keys are the RefineParams field names; rule_order
// takes "r3_first" or "paper" (or the proto's RULE_ORDER_R3_FIRST, RULE_ORDER_PAPER). An unknown
// key, a value of the wrong type or an unknown rule order is refused the same way everywhere.
#pragma once

#include <nlohmann/json.hpp>
#include <string_view>

#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::wire {

/// Sets the fields `object` names in `params`, keeping the others. Throws
/// ServiceError(invalid_argument) that names the bad key or value; ranges are the job
/// manager's to check.
void read_params(const nlohmann::json& object, v1::RefineParams* params);
/// The same from JSON text, which must be an object.
void parse_params(std::string_view json_text, v1::RefineParams* params);

}  // namespace mesh4d::wire
