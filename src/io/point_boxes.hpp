// The shapes the result file's writer gives HDF5: chunks of its datasets, and the hyperslab
// boxes that cover a list of flat point ranges.
#pragma once

#include <hdf5.h>

#include <cstddef>
#include <vector>

#include "io/output_file.hpp"

namespace cs::hdf5 {

// Chunks of about 1 MiB: big enough for efficient I/O, and equal to HDF5's
// default chunk cache so a reader (h5py, xarray) holds a whole chunk. Filling from the last
// dimension backwards keeps whole trailing rows (whole time series) inside one chunk.
std::vector<hsize_t> chunk_shape(const std::vector<hsize_t>& shape, std::size_t element_bytes);

// Selections: a flat, row-major run of grid points [begin, end) as a few rectangular hyperslabs.

struct Box {
  std::vector<hsize_t> start;
  std::vector<hsize_t> count;
};

// Ranges that touch are merged first: fewer boxes, and consecutive blocks become one box.
std::vector<PointRange> merged(const std::vector<PointRange>& ranges);

// The boxes of sorted runs, in row-major order: the order of the caller's data buffer. With a
// time dimension, each box holds the whole time series of its points.
std::vector<Box> boxes_of(const std::vector<PointRange>& runs,
                          const std::vector<hsize_t>& grid_dims, bool has_time_dim,
                          hsize_t time_length);

hsize_t elements_of(const Box& box);

}  // namespace cs::hdf5
