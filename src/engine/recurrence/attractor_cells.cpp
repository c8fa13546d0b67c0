#include "engine/recurrence/attractor_cells.hpp"

#include <algorithm>
#include <map>
#include <utility>

namespace cs {

AttractorCells::AttractorCells(std::vector<std::int64_t> cells, std::vector<bool> wraps)
    : cells_(std::move(cells)), wraps_(std::move(wraps)) {
  std::uint64_t stride = 1;
  for (std::int64_t n : cells_) {
    strides_.push_back(stride);
    stride *= static_cast<std::uint64_t>(n);
  }
}

int AttractorCells::root(int node) {
  while (parent_[static_cast<std::size_t>(node)] != node) {
    int& p = parent_[static_cast<std::size_t>(node)];
    p = parent_[static_cast<std::size_t>(p)];  // path halving
    node = p;
  }
  return node;
}

void AttractorCells::join(int a, int b) {
  a = root(a), b = root(b);
  if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
}

// The key itself and every cell that touches it: 3^n − 1 at most (fewer at the box's faces).
void AttractorCells::neighbours(std::uint64_t key, std::vector<std::uint64_t>& out) const {
  out.assign(1, key);
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    const std::int64_t n = cells_[k];
    const std::size_t before = out.size();
    for (std::size_t i = 0; i < before; ++i) {
      const std::uint64_t base = out[i];
      const auto index =
          static_cast<std::int64_t>((base / strides_[k]) % static_cast<std::uint64_t>(n));
      for (std::int64_t step : {-1, 1}) {
        std::int64_t j = index + step;
        if (wraps_[k]) j = (j + n) % n;
        if (j < 0 || j >= n || j == index) continue;
        out.push_back(base - static_cast<std::uint64_t>(index) * strides_[k] +
                      static_cast<std::uint64_t>(j) * strides_[k]);
      }
    }
  }
}

void AttractorCells::add(const std::vector<std::uint64_t>& keys) {
  if (keys.empty()) return;
  std::vector<int> nodes;
  for (std::uint64_t key : keys) {
    auto [it, added] = node_of_key_.try_emplace(key, static_cast<int>(parent_.size()));
    if (added) parent_.push_back(it->second);
    nodes.push_back(it->second);
  }
  for (int node : nodes) join(nodes.front(), node);
  std::vector<std::uint64_t> near;
  for (std::uint64_t key : keys) {
    neighbours(key, near);
    for (std::uint64_t other : near)
      if (auto it = node_of_key_.find(other); it != node_of_key_.end())
        join(nodes.front(), it->second);
  }
}

std::vector<std::vector<std::uint64_t>> AttractorCells::components() {
  std::map<int, std::vector<std::uint64_t>> by_root;
  for (const auto& [key, node] : node_of_key_) by_root[root(node)].push_back(key);
  std::vector<std::vector<std::uint64_t>> out;
  for (auto& [r, keys] : by_root) {
    std::sort(keys.begin(), keys.end());
    out.push_back(std::move(keys));
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  index_of_root_.clear();
  for (std::size_t i = 0; i < out.size(); ++i)
    index_of_root_[root(node_of_key_.at(out[i].front()))] = static_cast<int>(i);
  return out;
}

int AttractorCells::component_of(std::uint64_t key) const {
  const auto it = node_of_key_.find(key);
  if (it == node_of_key_.end()) return -1;
  int node = it->second;
  while (parent_[static_cast<std::size_t>(node)] != node)
    node = parent_[static_cast<std::size_t>(node)];
  const auto found = index_of_root_.find(node);
  return found == index_of_root_.end() ? -1 : found->second;
}

}  // namespace cs
