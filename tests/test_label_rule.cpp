// The label rule (engine/label_rule.hpp): the double well's sign of q1 where it applies, and
// numbering with a reason where it cannot, never a wrong sign.
#include <gtest/gtest.h>

#include <vector>

#include "engine/label_rule.hpp"

namespace cs {
namespace {

const LabelRule kSign{LabelRule::Kind::sign_of_q1, "left_well", "right_well"};

Attractor fixed_point(double q, double p = 0.0) { return {0, 1, {q, p}, {}}; }

std::vector<int> labels(const std::vector<Attractor>& table) {
  std::vector<int> out;
  for (const Attractor& a : table) out.push_back(a.label);
  return out;
}

TEST(LabelRule, NumberedCountsTheTableInItsOrder) {
  std::vector<Attractor> table{fixed_point(-1.0), fixed_point(0.0), fixed_point(1.0)};
  const Labelling l = apply_label_rule(LabelRule{}, "q", table);
  EXPECT_TRUE(l.by_rule);
  EXPECT_EQ(l.description, "");
  EXPECT_EQ(labels(table), (std::vector<int>{1, 2, 3}));
}

TEST(LabelRule, SignOfQ1GivesTheWells) {
  std::vector<Attractor> table{fixed_point(-1.0), fixed_point(1.0)};
  const Labelling l = apply_label_rule(kSign, "q", table);
  EXPECT_TRUE(l.by_rule);
  EXPECT_EQ(l.description, "the sign of q: left_well -1, undecided 0, right_well +1");
  EXPECT_EQ(labels(table), (std::vector<int>{-1, 1}));
  std::vector<Attractor> one{fixed_point(1.0)};  // a map of the right well alone
  EXPECT_TRUE(apply_label_rule(kSign, "q", one).by_rule);
  EXPECT_EQ(labels(one), (std::vector<int>{1}));
  std::vector<Attractor> none;
  EXPECT_TRUE(apply_label_rule(kSign, "q", none).by_rule);
}

// Each case the sign cannot tell apart falls back to 1..n, and says why.
TEST(LabelRule, FallsBackToNumbersWhereTheSignCannotLabel) {
  struct Case {
    std::vector<Attractor> table;
    std::string why;
  };
  Attractor cycle = fixed_point(1.0);
  cycle.period = 2;
  const std::vector<Case> cases{
      {{fixed_point(-1.0), fixed_point(0.0), fixed_point(1.0)}, "an attractor at q = 0"},
      {{fixed_point(-1.0), fixed_point(-0.5), fixed_point(1.0)}, "2 attractors at q < 0"},
      {{fixed_point(0.5), fixed_point(1.0)}, "2 attractors at q > 0"},
      {{fixed_point(-1.0), cycle}, "a cycle of period 2"}};
  for (const Case& c : cases) {
    std::vector<Attractor> table = c.table;
    const Labelling l = apply_label_rule(kSign, "q", table);
    EXPECT_FALSE(l.by_rule) << c.why;
    EXPECT_NE(l.description.find("numbered 1.." + std::to_string(table.size())), std::string::npos)
        << l.description;
    EXPECT_NE(l.description.find(c.why), std::string::npos) << l.description;
    std::vector<int> numbers;
    for (std::size_t k = 0; k < table.size(); ++k) numbers.push_back(static_cast<int>(k) + 1);
    EXPECT_EQ(labels(table), numbers) << c.why;
  }
}

}  // namespace
}  // namespace cs
