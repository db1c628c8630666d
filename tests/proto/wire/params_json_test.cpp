// RefineParams from JSON (proto/wire/params_json.h): the one parser of the client's --params
// file and the REST face. Everything it refuses is refused with a message that names the key
// or the value.
#include "wire/params_json.h"

#include <gtest/gtest.h>

#include <string>

#include "wire/service_error.h"

namespace mesh4d::wire {
namespace {

// The message of the ServiceError that parsing `text` throws ("" when it does not throw).
std::string refusal(const std::string& text) {
  v1::RefineParams params;
  try {
    parse_params(text, &params);
  } catch (const ServiceError& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << text;
    return e.what();
  }
  return "";
}

TEST(ParamsJson, ReadsEveryFieldByItsName) {
  v1::RefineParams p;
  parse_params(R"({"delta": 2.5, "radius_edge_bound": 1.8, "picking_ratio": 0.4,
                   "picking_trials": 7, "sliver_bound": 0.02, "max_interior_radius": 9,
                   "seed": 18446744073709551615, "vertex_budget": 1000, "threads": 3,
                   "extend_time_frames": 2, "rule_order": "paper", "sag_offset": false})",
               &p);
  EXPECT_EQ(p.delta(), 2.5);
  EXPECT_EQ(p.radius_edge_bound(), 1.8);
  EXPECT_EQ(p.picking_ratio(), 0.4);
  EXPECT_EQ(p.picking_trials(), 7u);
  EXPECT_EQ(p.sliver_bound(), 0.02);
  EXPECT_EQ(p.max_interior_radius(), 9);
  EXPECT_EQ(p.seed(), 18446744073709551615ull) << "every digit of a 64-bit seed";
  EXPECT_EQ(p.vertex_budget(), 1000u);
  EXPECT_EQ(p.threads(), 3u);
  EXPECT_EQ(p.extend_time_frames(), 2u);
  EXPECT_EQ(p.rule_order(), v1::RULE_ORDER_PAPER);
  EXPECT_TRUE(p.has_sag_offset()) << "false is said, not left to the default";
  EXPECT_FALSE(p.sag_offset());
  EXPECT_NE(refusal(R"({"sag_offset": "maybe"})").find("sag_offset"), std::string::npos);
}

TEST(ParamsJson, TakesTheShortAndTheProtoNamesOfTheRuleOrders) {
  for (const auto& [name, order] : {std::pair{"r3_first", v1::RULE_ORDER_R3_FIRST},
                                    {"RULE_ORDER_R3_FIRST", v1::RULE_ORDER_R3_FIRST},
                                    {"paper", v1::RULE_ORDER_PAPER},
                                    {"RULE_ORDER_PAPER", v1::RULE_ORDER_PAPER}}) {
    v1::RefineParams p;
    parse_params(std::string(R"({"rule_order": ")") + name + "\"}", &p);
    EXPECT_EQ(p.rule_order(), order) << name;
  }
}

TEST(ParamsJson, TakesTheShortAndTheProtoNamesOfTheTimeTopologies) {
  for (const auto& [name, topology] : {std::pair{"open", v1::TIME_TOPOLOGY_OPEN},
                                       {"TIME_TOPOLOGY_OPEN", v1::TIME_TOPOLOGY_OPEN},
                                       {"periodic", v1::TIME_TOPOLOGY_PERIODIC},
                                       {"TIME_TOPOLOGY_PERIODIC", v1::TIME_TOPOLOGY_PERIODIC}}) {
    v1::RefineParams p;
    parse_params(std::string(R"({"time_topology": ")") + name + "\"}", &p);
    EXPECT_EQ(p.time_topology(), topology) << name;
  }
  EXPECT_NE(refusal(R"({"time_topology": "circular"})")
                .find("time_topology 'circular' is not one of open, periodic"),
            std::string::npos);
}

TEST(ParamsJson, KeepsTheFieldsItDoesNotName) {
  v1::RefineParams p;
  p.set_delta(4);
  p.set_threads(2);
  parse_params(R"({"seed": 9})", &p);
  EXPECT_EQ(p.delta(), 4);
  EXPECT_EQ(p.threads(), 2u);
  EXPECT_EQ(p.seed(), 9u);
}

TEST(ParamsJson, RefusesWhatItDoesNotKnowNamingIt) {
  EXPECT_NE(refusal(R"({"deltaa": 3})").find("unknown parameter 'deltaa'"), std::string::npos);
  EXPECT_NE(refusal(R"({"rule_order": "fastest"})")
                .find("rule_order 'fastest' is not one of r3_first, paper"),
            std::string::npos);
  EXPECT_NE(refusal(R"({"rule_order": 1})").find("rule_order '1'"), std::string::npos);
  EXPECT_NE(refusal(R"({"delta": "five"})").find("delta"), std::string::npos);
  EXPECT_NE(refusal(R"({"threads": -2})").find("threads"), std::string::npos);
  EXPECT_NE(refusal(R"([1, 2])").find("JSON object"), std::string::npos);
  EXPECT_NE(refusal(R"({"delta": )").find("not valid JSON"), std::string::npos);
  EXPECT_EQ(refusal(R"({})"), "");
}

}  // namespace
}  // namespace mesh4d::wire
