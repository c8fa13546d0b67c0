// Chunks and hyperslab boxes of the result file's datasets (output_file.cpp).
#include "io/point_boxes.hpp"

#include <algorithm>
#include <functional>
#include <numeric>
#include <utility>

namespace cs::hdf5 {
namespace {

constexpr std::size_t kChunkBytes = std::size_t{1} << 20;


// Appends boxes covering flat range [begin, end) of the sub-grid dims[level..], whose leading
// indices (dims[0..level)) are fixed by `prefix`. Produces at most 2·(rank−level)−1 boxes: a
// partial leading row (recursively), one block of whole rows, a partial trailing row
// (recursively).
void decompose(std::int64_t begin, std::int64_t end, const std::vector<hsize_t>& dims,
               std::size_t level, std::vector<hsize_t>& prefix, std::vector<Box>& boxes) {
  if (begin >= end) return;
  std::int64_t row = 1;  // points per index of dims[level]: one "row" of the sub-grid
  for (std::size_t d = level + 1; d < dims.size(); ++d) row *= static_cast<std::int64_t>(dims[d]);

  const auto emit_rows = [&](std::int64_t first, std::int64_t count) {
    Box box;
    box.start = prefix;
    box.count.assign(prefix.size(), 1);
    box.start.push_back(static_cast<hsize_t>(first));
    box.count.push_back(static_cast<hsize_t>(count));
    for (std::size_t d = level + 1; d < dims.size(); ++d) {
      box.start.push_back(0);
      box.count.push_back(dims[d]);
    }
    boxes.push_back(std::move(box));
  };
  const auto recurse_in_row = [&](std::int64_t r, std::int64_t b, std::int64_t e) {
    prefix.push_back(static_cast<hsize_t>(r));
    decompose(b, e, dims, level + 1, prefix, boxes);
    prefix.pop_back();
  };

  if (row == 1) {  // last grid dimension: the range is already one box
    emit_rows(begin, end - begin);
    return;
  }
  std::int64_t first_row = begin / row;
  const bool whole_rows = begin % row == 0 && end % row == 0;
  if (first_row == (end - 1) / row && !whole_rows) {  // inside a single row
    recurse_in_row(first_row, begin % row, end - first_row * row);
    return;
  }
  if (begin % row != 0) {
    recurse_in_row(first_row, begin % row, row);
    ++first_row;
  }
  const std::int64_t full_end = end / row;  // rows [first_row, full_end) are whole
  if (full_end > first_row) emit_rows(first_row, full_end - first_row);
  if (end % row != 0) recurse_in_row(full_end, 0, end % row);
}

}  // namespace

std::vector<hsize_t> chunk_shape(const std::vector<hsize_t>& shape, std::size_t element_bytes) {
  const hsize_t target = std::max<hsize_t>(1, kChunkBytes / element_bytes);
  std::vector<hsize_t> chunk(shape.size(), 1);
  hsize_t elements = 1;
  for (std::size_t d = shape.size(); d-- > 0;) {
    if (elements * shape[d] <= target) {
      chunk[d] = shape[d];
      elements *= shape[d];
    } else {
      chunk[d] = std::max<hsize_t>(1, target / elements);
      break;  // leading dimensions stay at 1
    }
  }
  return chunk;
}

std::vector<PointRange> merged(const std::vector<PointRange>& ranges) {
  std::vector<PointRange> out;
  for (const PointRange& r : ranges) {
    if (r.begin == r.end) continue;
    if (!out.empty() && out.back().end == r.begin) {
      out.back().end = r.end;
    } else {
      out.push_back(r);
    }
  }
  return out;
}

std::vector<Box> boxes_of(const std::vector<PointRange>& runs,
                          const std::vector<hsize_t>& grid_dims, bool has_time_dim,
                          hsize_t time_length) {
  std::vector<Box> boxes;
  std::vector<hsize_t> prefix;
  for (const PointRange& r : runs) decompose(r.begin, r.end, grid_dims, 0, prefix, boxes);
  if (has_time_dim)
    for (Box& box : boxes) {
      box.start.push_back(0);
      box.count.push_back(time_length);
    }
  return boxes;
}

hsize_t elements_of(const Box& box) {
  return std::accumulate(box.count.begin(), box.count.end(), hsize_t{1}, std::multiplies<>());
}

}  // namespace cs::hdf5
