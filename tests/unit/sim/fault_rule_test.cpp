#include <gtest/gtest.h>

#include "sim/table_fault_rule.hpp"

namespace hrgbench::drivers::sim {
namespace {

TEST(FaultRule, ParsesEveryKindAndRoundTrips) {
  for (const std::string text :
       {"input:4=late*1", "holding:2=exception", "input:0=wrong-length*3"}) {
    const auto rule = ParseFaultRule(text);
    ASSERT_TRUE(rule) << rule.error();
    EXPECT_EQ(rule->ToString(), text);
  }
  const auto rule = ParseFaultRule("holding:6=exception");
  ASSERT_TRUE(rule);
  EXPECT_EQ(rule->table, RegisterTable::kHolding);
  EXPECT_EQ(rule->address, 6);
  EXPECT_EQ(rule->kind, FaultKind::kException);
  EXPECT_EQ(rule->count, -1);
}

TEST(FaultRule, RejectsMalformedText) {
  for (const std::string text : {"", "input4=late", "coils:1=late", "input:x=late", "input:1=slow",
                                 "input:1=late*0", "input:70000=late"}) {
    EXPECT_FALSE(ParseFaultRule(text)) << text;
  }
}

}  // namespace
}  // namespace hrgbench::drivers::sim
