#include "engine/results.hpp"

#include <algorithm>

namespace cs {

void CompactColumn::assign(const std::vector<double>& values) {
  double low = 0.0, high = 0.0;
  for (double v : values) low = std::min(low, v), high = std::max(high, v);
  if (low >= INT8_MIN && high <= INT8_MAX) data_ = std::vector<std::int8_t>(values.begin(), values.end());
  else if (low >= INT16_MIN && high <= INT16_MAX) data_ = std::vector<std::int16_t>(values.begin(), values.end());
  else data_ = std::vector<std::int32_t>(values.begin(), values.end());
}

void CompactColumn::expand(std::vector<double>& out) const {
  std::visit([&](const auto& v) { out.assign(v.begin(), v.end()); }, data_);
}

std::size_t CompactColumn::size() const {
  return std::visit([](const auto& v) { return v.size(); }, data_);
}

void CompactColumn::clear() { data_ = std::vector<std::int8_t>(); }

BlockResults::BlockResults(PointRange r, const std::vector<ColumnSpec>& specs) : range(r) {
  auto n = r.end - r.begin;
  for (const auto& s : specs) {
    columns.emplace_back(static_cast<std::size_t>(s.grows ? 0 : s.per_block ? s.width : n * s.width), 0.0);
    grows.push_back(s.grows);
  }
}

}  // namespace cs
