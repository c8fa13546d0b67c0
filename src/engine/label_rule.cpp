#include "engine/label_rule.hpp"

#include <fmt/format.h>

namespace cs {
namespace {

void number(std::vector<Attractor>& table) {
  for (std::size_t k = 0; k < table.size(); ++k) table[k].label = static_cast<int>(k) + 1;
}

// Why the sign of q1 cannot label `table` (empty if it can): each attractor a fixed point off
// q1 = 0, at most one on either side.
std::string sign_conflict(const std::vector<Attractor>& table, const std::string& q1) {
  int negative = 0, positive = 0;
  for (const Attractor& a : table) {
    if (a.period != 1) return fmt::format("a cycle of period {}", a.period);
    const double x = a.point.front();
    if (!(x < 0.0 || x > 0.0)) return fmt::format("an attractor at {} = {}", q1, x);
    ++(x < 0.0 ? negative : positive);
  }
  if (negative > 1) return fmt::format("{} attractors at {} < 0", negative, q1);
  if (positive > 1) return fmt::format("{} attractors at {} > 0", positive, q1);
  return "";
}

std::string meaning(const LabelRule& rule, const std::string& q1) {
  return fmt::format("the sign of {}: {} -1, undecided 0, {} +1", q1, rule.negative,
                     rule.positive);
}

}  // namespace

Labelling apply_label_rule(const LabelRule& rule, const std::string& first_position,
                           std::vector<Attractor>& table) {
  number(table);
  if (rule.kind == LabelRule::Kind::numbered) return {true, ""};
  const std::string described = meaning(rule, first_position);
  const std::string conflict = sign_conflict(table, first_position);
  if (!conflict.empty())
    return {false, fmt::format("numbered 1..{} in the table's order, not by {}, which cannot "
                               "label these attractors: {}",
                               table.size(), described, conflict)};
  for (Attractor& a : table) a.label = a.point.front() < 0.0 ? -1 : 1;
  return {true, described};
}

Labelling apply_label_rule(const LabelRule& rule, const std::string& first_position,
                           std::vector<Attractor>& table,
                           std::vector<std::vector<Attractor>>& along) {
  Labelling labelling = apply_label_rule(rule, first_position, table);
  const auto branch = [&](const Attractor& a) -> Attractor& {
    return table[static_cast<std::size_t>(a.label - 1)];  // a.label: its branch's number
  };
  if (labelling.by_rule && rule.kind != LabelRule::Kind::numbered) {
    int crossing = 0;  // the first branch found on both sides of q1 = 0 (or on it)
    for (const auto& at_value : along)
      for (const Attractor& a : at_value) {
        const double x = a.point.front(), side = branch(a).point.front();
        if (crossing == 0 && !((x < 0.0 && side < 0.0) || (x > 0.0 && side > 0.0)))
          crossing = a.label;
      }
    if (crossing != 0) {
      number(table);
      labelling = {false, fmt::format("numbered 1..{} in order of appearance, not by {}, which "
                                      "cannot label these attractors: attractor {} meets {} = 0 "
                                      "along the continuation",
                                      table.size(), meaning(rule, first_position), crossing,
                                      first_position)};
    }
  }
  for (auto& at_value : along)
    for (Attractor& a : at_value) a.label = branch(a).label;
  return labelling;
}

}  // namespace cs
