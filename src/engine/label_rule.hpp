// The labels of a run's attractors, by the scene's rule (SceneInfo::label_rule): numbers 1..n in
// the table's order for any scene, or a scene's own meaning (the double well's −1/+1 for its
// left and right wells). A rule that cannot label the attractors found (two on one side, one
// at q1 = 0 — not the saddle a lane that started on it settled on, which the table refuses as
// unstable where its exact λ₁ is known: attractor_table.hpp —, a cycle) never mislabels: the table is
// numbered instead, and the file and the log say why (BasinSummary::labels).
#pragma once

#include <string>
#include <vector>

#include "engine/attractor_table.hpp"
#include "physics/scene_catalog.hpp"

namespace cs {

// Sets every attractor's label in `table` (in its sorted order). `first_position` names q1.
Labelling apply_label_rule(const LabelRule& rule, const std::string& first_position,
                           std::vector<Attractor>& table);

// The same for a continuation (attractor_continuation.hpp): `table` the branches in order of
// appearance, `along[k]` the attractors at the axis' k-th value, labelled by branch number
// (1..n) on entry and by their branch's label on return. The sign of q1 labels a branch only
// if every attractor along it lies on its side: one that crosses q1 = 0 is numbered instead.
Labelling apply_label_rule(const LabelRule& rule, const std::string& first_position,
                           std::vector<Attractor>& table,
                           std::vector<std::vector<Attractor>>& along);

}  // namespace cs
