// Attractors followed along a parameter (INTERFACE.md, "Attractors of every kind"; docs/basins.md,
// "Continuation"). When the grid's first axis is a scene parameter and other axes follow, the
// table is built per value of that axis (the same merge, in block order, as for a whole map),
// and the attractors at each value are matched to the branches already known — nearest pairs
// first, one to one, up to a threshold — so that an attractor that moves keeps its label; one
// left unmatched starts a branch (a label) of its own. As Attractors.jl's MatchBySSSetDistance
// with use_vanished = true, but with ties broken by index (the table depends on the spec alone),
// attractors matched only to branches of their own period (a cycle of period 2 is not the fixed
// point it bifurcated from), a move admitted only if it is short beside the spacing of the
// attractors (match_threshold), and pairs ranked by the distance to the branch's linear
// extrapolation from its last two points, admitted when either it or the distance to the last
// point is short enough (a steady move is followed beyond the threshold).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "engine/attractor_table.hpp"
#include "engine/run_plan.hpp"

namespace cs {

// The axis the attractors are continued along: the grid's first axis when it sets a scene
// parameter and other axes follow; `values` = 1 (one table for the whole grid) otherwise.
struct ContinuationAxis {
  bool along_parameter = false;
  std::int64_t values = 1;
  std::int64_t points_per_value = 1;  // grid points sharing one value (the axes after it)
  std::int64_t first_point = 0;       // the plan's first point (RunPlan::point_offset)
  std::int64_t value_of(std::int64_t point) const {
    return (point - first_point) / points_per_value;
  }
};
ContinuationAxis continuation_axis(const RunPlan& plan);

// How far an attractor may move between neighbouring values and keep its label (max norm over
// q, p, angles modulo their period): measures.basin.continuation_threshold, by default a
// tenth of the widest side of the box of the map (the
// recurrence mapper's box; by default each variable's range over the grid widened by half,
// at least ±½), i.e. 10 of the recurrence mapper's default cells; and at each value no more
// than kSeparationShare of the smallest distance between two attractors there or at the value
// before (continue_attractors). Under a third, the move of an attractor is shorter than the
// distance from its new place to any other attractor's old one: nearest is then unambiguous.
double match_threshold(const RunPlan& plan);
inline constexpr double kSeparationShare = 1.0 / 3.0;

// The distance between two attractors of one period: between their points (max norm, angles
// modulo their period) for points and cycles; for recurrence attractors (period 0) the
// smallest distance between the centres of a cell of each (their cells as far as the table
// names them).
double attractor_distance(const RunPlan& plan, const Attractor& a, const Attractor& b);

using AttractorDistance = std::function<double(const Attractor&, const Attractor&)>;

struct Continuation {
  // One per branch, in order of first appearance (value, then the table's order there): its
  // point and cells where it was first found; label = its index + 1.
  std::vector<Attractor> branches;
  // Per value, the attractors found there (the table's order), labelled by their branch.
  std::vector<std::vector<Attractor>> along;
};

// Matches the tables of consecutive values (`tables[k]` at `values[k]`, each sorted as the
// table of a whole map) into branches. Pairs (branch, attractor) of equal period are taken in
// increasing distance (ties: branch, then attractor index) while the distance is within
// `threshold` and kSeparationShare of the separation of the attractors at values k and k − 1; every branch seen so far takes part, not only those at the previous value, so an
// attractor missed at one value (no lane fell in its basin) keeps its label when it returns.
// `angle_period` (per q.., p..; 0: not an angle) folds the extrapolation's steps.
Continuation continue_attractors(std::vector<std::vector<Attractor>> tables,
                                 const std::vector<double>& values,
                                 const AttractorDistance& distance, double threshold,
                                 const std::vector<double>& angle_period);

}  // namespace cs
