// Attractors found by recurrences (engine/recurrence/), told apart by their cells: each settled
// lane names the cells it located by its smallest key and a bottom-k sketch (CellSet::sketch);
// two such sets are one attractor when a cell of one equals or touches (a face, an edge or a
// corner; angles wrap) a cell of the other, and the relation is closed transitively. The
// components do not depend on the order in which sets are added — the same table from the
// same lanes for any cut into blocks, ranks and threads — and are numbered by their smallest
// key.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace cs {

class AttractorCells {
 public:
  // The grid's cells per variable and which variables wrap round (angles).
  AttractorCells(std::vector<std::int64_t> cells, std::vector<bool> wraps);

  // One lane's (or candidate's) keys: they belong to one attractor.
  void add(const std::vector<std::uint64_t>& keys);

  // The attractors, each its keys in increasing order, in increasing order of smallest key.
  std::vector<std::vector<std::uint64_t>> components();

  // The index in components() of the attractor holding `key`, −1 if none (after components()).
  int component_of(std::uint64_t key) const;

 private:
  int root(int node);
  void join(int a, int b);
  void neighbours(std::uint64_t key, std::vector<std::uint64_t>& out) const;

  std::vector<std::int64_t> cells_;
  std::vector<bool> wraps_;
  std::vector<std::uint64_t> strides_;
  std::unordered_map<std::uint64_t, int> node_of_key_;
  std::vector<int> parent_;
  std::unordered_map<int, int> index_of_root_;  // set by components()
};

}  // namespace cs
