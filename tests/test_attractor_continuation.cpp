// The continuation's matcher (engine/attractor_continuation.hpp) on synthetic tables: an
// attractor that moves by less than the threshold keeps its label, one that appears or vanishes
// gets a label of its own, one that returns gets its old one back, two that swap their sorted
// positions keep theirs, a steady move is followed by its extrapolation, a jump as long as the
// attractors' spacing is no move; and the label rule along a continuation.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/attractor_continuation.hpp"
#include "engine/label_rule.hpp"

namespace cs {
namespace {

Attractor at(double q1, double q2 = 0.0, int period = 1) { return {0, period, {q1, q2}, {}}; }

double max_norm(const Attractor& a, const Attractor& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < a.point.size(); ++k)
    d = std::fmax(d, std::fabs(a.point[k] - b.point[k]));
  return d;
}

// The labels at each value, in each table's order.
std::vector<std::vector<int>> labels(const Continuation& c) {
  std::vector<std::vector<int>> out;
  for (const auto& table : c.along) {
    out.emplace_back();
    for (const Attractor& a : table) out.back().push_back(a.label);
  }
  return out;
}

Continuation run(std::vector<std::vector<Attractor>> tables, double threshold = 0.2) {
  std::vector<double> values;
  for (std::size_t k = 0; k < tables.size(); ++k) values.push_back(0.1 * static_cast<double>(k));
  return continue_attractors(std::move(tables), values, max_norm, threshold, {0.0, 0.0});
}

using Labels = std::vector<std::vector<int>>;

TEST(Continuation, AnAttractorThatMovesLessThanTheThresholdKeepsItsLabel) {
  // Two fixed points at ±a, a = 0.8 .. 1.2: each moves by 0.1 < 0.2 per value.
  std::vector<std::vector<Attractor>> tables;
  for (double a : {0.8, 0.9, 1.0, 1.1, 1.2}) tables.push_back({at(-a), at(a)});
  const Continuation c = run(tables);
  ASSERT_EQ(c.branches.size(), 2u);
  EXPECT_EQ(labels(c), (Labels{{1, 2}, {1, 2}, {1, 2}, {1, 2}, {1, 2}}));
  EXPECT_EQ(c.branches[0].point[0], -0.8);  // the branch's point: where it was first found
  EXPECT_EQ(c.branches[1].point[0], 0.8);
  EXPECT_EQ(c.along[4][1].point[0], 1.2);  // and where it is at each value
}

TEST(Continuation, AMoveBeyondTheThresholdIsANewAttractor) {
  const Continuation c = run({{at(0.0)}, {at(0.25)}});
  EXPECT_EQ(labels(c), (Labels{{1}, {2}}));
  EXPECT_EQ(c.branches.size(), 2u);
}

TEST(Continuation, AnAttractorThatAppearsGetsALabelOfItsOwn) {
  const Continuation c = run({{at(-1.0)}, {at(-1.0), at(1.0)}, {at(-1.0), at(1.05)}});
  EXPECT_EQ(labels(c), (Labels{{1}, {1, 2}, {1, 2}}));
  ASSERT_EQ(c.branches.size(), 2u);
  EXPECT_EQ(c.branches[1].point[0], 1.0);
}

TEST(Continuation, AnAttractorThatVanishesFreesNoLabelAndOneThatReturnsGetsItsOwnBack) {
  // B vanishes at the second value, returns at the third; C appears far from anything known.
  const Continuation c =
      run({{at(-1.0), at(1.0)}, {at(-1.0)}, {at(-1.0), at(1.02)}, {at(-1.0), at(1.02), at(3.0)}});
  EXPECT_EQ(labels(c), (Labels{{1, 2}, {1}, {1, 2}, {1, 2, 3}}));
  // An attractor that vanishes while another appears elsewhere: not matched (threshold).
  const Continuation d = run({{at(-1.0), at(1.0)}, {at(-1.0), at(2.0)}});
  EXPECT_EQ(labels(d), (Labels{{1, 2}, {1, 3}}));
}

TEST(Continuation, TwoThatSwapTheirSortedPositionsKeepTheirLabels) {
  // Sorted by q1: A (0, 1) before B (0.05, −1); then B' (0, −1) before A' (0.1, 1).
  const Continuation c = run({{at(0.0, 1.0), at(0.05, -1.0)}, {at(0.0, -1.0), at(0.1, 1.0)}});
  EXPECT_EQ(labels(c), (Labels{{1, 2}, {2, 1}}));
}

TEST(Continuation, ASteadyMoveIsFollowedBeyondTheThresholdByItsExtrapolation) {
  // Steps 0.15, 0.2, 0.25 against a threshold of 0.2: the last is 0.05 from where the first two
  // say it goes (0.55); from the last point alone it would be a new attractor.
  const Continuation c = run({{at(0.0)}, {at(0.15)}, {at(0.35)}, {at(0.6)}});
  EXPECT_EQ(labels(c), (Labels{{1}, {1}, {1}, {1}}));
  const Continuation jump = run({{at(0.0)}, {at(0.15)}, {at(0.35)}, {at(0.8)}});
  EXPECT_EQ(labels(jump), (Labels{{1}, {1}, {1}, {2}}));
}

TEST(Continuation, AJumpAsLongAsTheAttractorsSpacingIsNoMove) {
  // A pendulum's maxima ±3 at one value, its minima −2, 0, 2 at the next: within the threshold
  // (5) but a third of their spacing (2) is 2/3 < 1: no branch goes on.
  const Continuation c = run({{at(-3.0), at(3.0)}, {at(-2.0), at(0.0), at(2.0)}}, 5.0);
  EXPECT_EQ(labels(c), (Labels{{1, 2}, {3, 4, 5}}));
  // Moves under a third of the spacing are moves.
  const Continuation d = run({{at(-3.0), at(3.0)}, {at(-2.5), at(2.5)}}, 5.0);
  EXPECT_EQ(labels(d), (Labels{{1, 2}, {1, 2}}));
}

TEST(Continuation, OnlyAttractorsOfOnePeriodAreMatched) {
  // A fixed point that doubles its period is a new attractor, however near.
  const Continuation c = run({{at(1.0)}, {at(1.0, 0.0, 2)}});
  EXPECT_EQ(labels(c), (Labels{{1}, {2}}));
}

const LabelRule kSign{LabelRule::Kind::sign_of_q1, "left_well", "right_well"};

TEST(Continuation, TheDoubleWellsSignHoldsAlongTheContinuation) {
  std::vector<std::vector<Attractor>> tables;
  for (double a : {0.8, 1.0, 1.2}) tables.push_back({at(-a), at(a)});
  Continuation c = run(tables);
  const Labelling l = apply_label_rule(kSign, "q", c.branches, c.along);
  EXPECT_TRUE(l.by_rule);
  EXPECT_EQ(c.branches[0].label, -1);
  EXPECT_EQ(c.branches[1].label, 1);
  EXPECT_EQ(labels(c), (Labels{{-1, 1}, {-1, 1}, {-1, 1}}));
}

TEST(Continuation, ABranchThatCrossesQ1EqualsZeroIsNumbered) {
  Continuation c = run({{at(-0.05), at(1.0)}, {at(0.05), at(1.0)}});
  const Labelling l = apply_label_rule(kSign, "q", c.branches, c.along);
  EXPECT_FALSE(l.by_rule);
  EXPECT_NE(l.description.find("attractor 1 meets q = 0"), std::string::npos) << l.description;
  EXPECT_EQ(labels(c), (Labels{{1, 2}, {1, 2}}));
}

}  // namespace
}  // namespace cs
